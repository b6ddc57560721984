#include "polycut/common/error.hpp"

#include <gtest/gtest.h>

using namespace polycut;

TEST(Error, MessagesNameTheLocation)
{
    const FileError fe("a.msh", 12, "bad node count");
    EXPECT_STREQ(fe.what(), "a.msh:12: bad node count");
    EXPECT_EQ(fe.line(), 12);
    const MeshError me(3, 1, "non-planar face");
    EXPECT_STREQ(me.what(), "cell 3 face 1: non-planar face");
    const SceneError se("/material/poisson_ratio", "must be in [0, 0.5)");
    EXPECT_EQ(se.where(), "/material/poisson_ratio");
    EXPECT_EQ(se.problem(), "must be in [0, 0.5)");
}
