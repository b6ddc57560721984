// OpenIGTLink messages of polycut-igtl, made and read with the OpenIGTLink library
// (libopenigtlink-dev): the surface as POLYDATA (points, triangles as polygons, the cut tag as a
// cell scalar) and TRANSFORM messages read as tool poses. Lengths on the OpenIGTLink side are
// in millimetres (3D Slicer's unit), polycut's in metres; `mm_per_m` converts.
#pragma once

#include "polycut/protocol/stream.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace polycut::igtl_bridge {

/// Name of the cell scalar that carries the tag of each triangle: 1 skin, 2 cut surface. It has
/// 9 equal components (see pack_polydata).
inline constexpr const char* kCutTagName = "cut_tag";
/// Name of the point scalar: 2 on a vertex of a cut triangle, else 1 (one component; what a
/// viewer colours by most easily).
inline constexpr const char* kCutTagPointName = "cut_tag_point";

/// A packed OpenIGTLink message (header + body), ready to send.
using Packed = std::vector<std::uint8_t>;

/// POLYDATA named `device` holding the surface: positions scaled by mm_per_m, every triangle as
/// a polygon, the cell scalar kCutTagName and the point scalar kCutTagPointName.
Packed pack_polydata(
    const protocol::SurfaceFrame& surface, const std::string& device, double mm_per_m);

/// A tool pose from a TRANSFORM: the origin and the tool's local z axis (unit) in polycut's
/// world [m].
struct ToolPose {
    std::string device; ///< the message's device name
    std::array<double, 3> origin {}; ///< [m]
    std::array<double, 3> axis {}; ///< unit vector
};

/// Reads the header of an OpenIGTLink message (58 bytes): device type and name, body size.
struct Header {
    std::string type; ///< "TRANSFORM", "POLYDATA", ...
    std::string device;
    std::uint64_t body_size = 0; ///< [bytes]
};
std::optional<Header> unpack_header(const std::uint8_t* bytes, std::size_t size);

/// A TRANSFORM message (header + body) as a tool pose; nullopt when the CRC or the matrix is bad
/// (non-finite, or a zero z axis).
std::optional<ToolPose> unpack_transform(const std::vector<std::uint8_t>& message, double mm_per_m);

/// A TRANSFORM message for `pose` (for tests and scripted tools): the rotation takes local z to
/// `axis`; the origin is scaled by mm_per_m.
Packed pack_transform(const ToolPose& pose, double mm_per_m);

/// Size of the OpenIGTLink header [bytes].
std::size_t header_size();

} // namespace polycut::igtl_bridge
