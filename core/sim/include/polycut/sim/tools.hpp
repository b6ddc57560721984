// Client-driven rigid tools and contact reports of sim::Simulation (issue 15 item 1). A tool is
// a rigid shape the client moves at its input device's rate; the tissue touches it, the scene's
// obstacles and (through the same penalty) nothing else. Its pose is applied at the next tick
// boundary, and its velocity over a tick is its motion since the previous tick over dt.
#pragma once

#include "polycut/common/types.hpp"

#include <optional>
#include <string>

namespace polycut::sim {

/// A tool's pose: the tool frame's origin and orientation in the world.
struct ToolPose {
    Vec3 position = Vec3::Zero(); ///< [m]
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity(); ///< unit quaternion
};

/// A tool's shape in its own frame (the pose puts it in the world).
struct ToolSpec {
    enum class Kind {
        Sphere, ///< a ball of `radius` centred at the origin (a probe tip)
        Capsule, ///< a shaft: `length` along local z centred at the origin, `radius` around it
        Blade, ///< a thin box of edge lengths `size` (x: length, y: height, z: thickness)
    };
    Kind kind = Kind::Sphere;
    double radius = 0.005; ///< Sphere, Capsule [m], > 0
    double length = 0.05; ///< Capsule: axis length [m], >= 0
    Vec3 size = Vec3(0.03, 0.01, 0.001); ///< Blade [m], each > 0
    ToolPose pose;
    /// Penalty stiffness [N/m^3] and Coulomb friction of this tool; absent: the scene's
    /// `contact` values
    std::optional<double> stiffness, friction;
};

/// What the tissue does to a body (a tool or an obstacle) after a step.
struct BodyReaction {
    std::string kind; ///< "tool" or "obstacle"
    long id = 0; ///< the tool id, or the obstacle's index in the scene
    std::string name; ///< obstacle name ("" for tools and unnamed obstacles)
    Vec3 force = Vec3::Zero(); ///< force on the body [N] (what a haptic device renders)
    Vec3 torque = Vec3::Zero(); ///< about the body's pose position (tool frame origin) [N m]
    int points = 0; ///< tissue samples inside it
    double max_depth = 0; ///< deepest penetration [m]
};

} // namespace polycut::sim
