// OpenIGTLink POLYDATA and TRANSFORM messages (see igtl_messages.hpp).
#include "igtl_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_header.h>

namespace polycut::igtl_bridge {

namespace {

Packed copy_pack(igtl::MessageBase& message) {
    const auto* p = static_cast<const std::uint8_t*>(message.GetPackPointer());
    return Packed(p, p + message.GetPackSize());
}

} // namespace

std::size_t header_size() {
    return IGTL_HEADER_SIZE;
}

Packed pack_polydata(
    const protocol::SurfaceFrame& surface, const std::string& device, double mm_per_m) {
    const std::size_t nv = surface.positions.size() / 3;
    const std::size_t nt = surface.triangles.size() / 3;
    auto points = igtl::PolyDataPointArray::New();
    points->SetNumberOfPoints(int(nv));
    for (std::size_t i = 0; i < nv; ++i) {
        points->SetPoint(unsigned(i), igtlFloat32(surface.positions[3 * i] * mm_per_m),
            igtlFloat32(surface.positions[3 * i + 1] * mm_per_m),
            igtlFloat32(surface.positions[3 * i + 2] * mm_per_m));
    }
    auto polygons = igtl::PolyDataCellArray::New();
    // OpenIGTLink's C packer (igtl_polydata.c, 1.11 to 3.x) sizes every attribute whose type is
    // not a point scalar, vector or normal as a 9-component tensor, cell scalars included; so the
    // cell tag travels as 9 equal components, which that code packs and unpacks consistently.
    constexpr int kCellComponents = 9;
    std::vector<igtlFloat32> cell_tags(nt * kCellComponents, 1.0f);
    std::vector<igtlFloat32> point_tags(nv, 1.0f);
    for (std::size_t t = 0; t < nt; ++t) {
        igtlUint32 cell[3] = { surface.triangles[3 * t], surface.triangles[3 * t + 1],
            surface.triangles[3 * t + 2] };
        polygons->AddCell(3, cell);
        const igtlFloat32 tag = t < surface.tags.size() ? igtlFloat32(surface.tags[t]) : 1.0f;
        std::fill_n(cell_tags.begin() + long(t * kCellComponents), kCellComponents, tag);
        for (const igtlUint32 v : cell) {
            if (v < nv) {
                point_tags[v] = std::max(point_tags[v], tag);
            }
        }
    }
    auto cut = igtl::PolyDataAttribute::New();
    cut->SetType(igtl::PolyDataAttribute::CELL_SCALAR, kCellComponents);
    cut->SetName(kCutTagName);
    cut->SetSize(igtlUint32(nt));
    auto cut_points = igtl::PolyDataAttribute::New();
    cut_points->SetType(igtl::PolyDataAttribute::POINT_SCALAR, 1);
    cut_points->SetName(kCutTagPointName);
    cut_points->SetSize(igtlUint32(nv));
    if (nt > 0) {
        cut->SetData(cell_tags.data());
    }
    if (nv > 0) {
        cut_points->SetData(point_tags.data());
    }
    auto message = igtl::PolyDataMessage::New();
    message->SetDeviceName(device.c_str());
    message->SetPoints(points);
    message->SetPolygons(polygons);
    // OpenIGTLink 1.11 packs every cell array it has a pointer to and crashes on a missing one.
    message->SetVertices(igtl::PolyDataCellArray::New());
    message->SetLines(igtl::PolyDataCellArray::New());
    message->SetTriangleStrips(igtl::PolyDataCellArray::New());
    message->AddAttribute(cut);
    message->AddAttribute(cut_points);
    message->Pack();
    return copy_pack(*message);
}

std::optional<Header> unpack_header(const std::uint8_t* bytes, std::size_t size) {
    if (size < IGTL_HEADER_SIZE) {
        return std::nullopt;
    }
    auto header = igtl::MessageHeader::New();
    header->InitPack();
    std::memcpy(header->GetPackPointer(), bytes, IGTL_HEADER_SIZE);
    if (!(header->Unpack() & igtl::MessageHeader::UNPACK_HEADER)) {
        return std::nullopt;
    }
    return Header { header->GetDeviceType(), header->GetDeviceName(),
        std::uint64_t(header->GetBodySizeToRead()) };
}

std::optional<ToolPose> unpack_transform(const std::vector<std::uint8_t>& bytes, double mm_per_m) {
    if (bytes.size() < IGTL_HEADER_SIZE) {
        return std::nullopt;
    }
    auto header = igtl::MessageHeader::New();
    header->InitPack();
    std::memcpy(header->GetPackPointer(), bytes.data(), IGTL_HEADER_SIZE);
    header->Unpack();
    auto message = igtl::TransformMessage::New();
    message->SetMessageHeader(header);
    message->AllocatePack();
    if (std::size_t(message->GetPackBodySize()) != bytes.size() - IGTL_HEADER_SIZE) {
        return std::nullopt;
    }
    std::memcpy(message->GetPackBodyPointer(), bytes.data() + IGTL_HEADER_SIZE,
        bytes.size() - IGTL_HEADER_SIZE);
    if (!(message->Unpack(1) & igtl::MessageHeader::UNPACK_BODY)) {
        return std::nullopt; // CRC mismatch or a short body
    }
    igtl::Matrix4x4 m;
    message->GetMatrix(m);
    ToolPose pose;
    pose.device = message->GetDeviceName();
    double norm = 0;
    for (int r = 0; r < 3; ++r) {
        pose.origin[r] = double(m[r][3]) / mm_per_m;
        pose.axis[r] = double(m[r][2]);
        norm += pose.axis[r] * pose.axis[r];
    }
    norm = std::sqrt(norm);
    if (!std::isfinite(norm) || norm < 1e-6 || !std::isfinite(pose.origin[0])
        || !std::isfinite(pose.origin[1]) || !std::isfinite(pose.origin[2])) {
        return std::nullopt;
    }
    for (double& a : pose.axis) {
        a /= norm;
    }
    return pose;
}

Packed pack_transform(const ToolPose& pose, double mm_per_m) {
    // Columns: x, y orthogonal to the axis, then the axis (local z), then the origin.
    const auto& z = pose.axis;
    std::array<double, 3> helper = std::abs(z[0]) < 0.9 ? std::array<double, 3> { 1, 0, 0 }
                                                        : std::array<double, 3> { 0, 1, 0 };
    std::array<double, 3> x { helper[1] * z[2] - helper[2] * z[1],
        helper[2] * z[0] - helper[0] * z[2], helper[0] * z[1] - helper[1] * z[0] };
    const double n = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (double& v : x) {
        v /= n;
    }
    const std::array<double, 3> y { z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0] };
    igtl::Matrix4x4 m;
    igtl::IdentityMatrix(m);
    for (int r = 0; r < 3; ++r) {
        m[r][0] = float(x[r]);
        m[r][1] = float(y[r]);
        m[r][2] = float(z[r]);
        m[r][3] = float(pose.origin[r] * mm_per_m);
    }
    auto message = igtl::TransformMessage::New();
    message->SetDeviceName(pose.device.c_str());
    message->SetMatrix(m);
    message->Pack();
    return copy_pack(*message);
}

} // namespace polycut::igtl_bridge
