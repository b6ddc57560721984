#include "polycut/common/stats.hpp"

#include <gtest/gtest.h>

using namespace polycut;

TEST(Stats, PercentilesInterpolateOrderStatistics)
{
    std::vector<double> s;
    for (int i = 100; i >= 0; --i)
        s.push_back(double(i));
    const Summary sum = summarize(s);
    EXPECT_EQ(sum.count, 101);
    EXPECT_DOUBLE_EQ(sum.median, 50.0);
    EXPECT_DOUBLE_EQ(sum.p99, 99.0);
    EXPECT_DOUBLE_EQ(sum.min, 0.0);
    EXPECT_DOUBLE_EQ(sum.max, 100.0);
    EXPECT_DOUBLE_EQ(sum.mean, 50.0);
    EXPECT_DOUBLE_EQ(percentile({ 1.0, 2.0 }, 25), 1.25);
}

TEST(Stats, EmptySampleGivesZeros)
{
    const Summary sum = summarize({});
    EXPECT_EQ(sum.count, 0);
    EXPECT_EQ(sum.median, 0.0);
}
