// to_string() of the scene enums: the names of names.hpp, the tables the parser reads.
#include "names.hpp"

namespace polycut::scene {
using namespace detail;

const char* to_string(Geometry::Kind v) {
    return name_of(kGeometryKind, v);
}
const char* to_string(Obstacle::Kind v) {
    return name_of(kObstacleKind, v);
}
const char* to_string(Method v) {
    return name_of(kMethod, v);
}
const char* to_string(Elements v) {
    return name_of(kElements, v);
}
const char* to_string(TetSplit v) {
    return name_of(kTetSplit, v);
}
const char* to_string(Shape v) {
    return v == Shape::None               ? ""
        : v == Shape::TruncatedOctahedron ? name_of(kHullShape, v)
                                          : name_of(kImplicitShape, v);
}
const char* to_string(NodeOrder v) {
    return name_of(kNodeOrder, v);
}
const char* to_string(Repair v) {
    return name_of(kRepair, v);
}
const char* to_string(Components v) {
    return name_of(kComponents, v);
}
const char* to_string(OctreeObject v) {
    return name_of(kOctreeObject, v);
}
const char* to_string(OctreeKeep v) {
    return name_of(kOctreeKeep, v);
}
const char* to_string(SolverType v) {
    return name_of(kSolverType, v);
}
const char* to_string(Preconditioner v) {
    return name_of(kPreconditioner, v);
}
const char* to_string(WarmStart v) {
    return name_of(kWarmStart, v);
}
const char* to_string(Distribution v) {
    return name_of(kDistribution, v);
}
const char* to_string(CutMethod v) {
    return name_of(kCutMethod, v);
}
const char* to_string(ToolShape v) {
    return name_of(kToolShape, v);
}
const char* to_string(basis::PolyRule v) {
    return name_of(kPolyRule, v);
}
const char* to_string(basis::VolumetricRule v) {
    return name_of(kVolumetric, v);
}
const char* to_string(dg::Flux v) {
    return name_of(kFlux, v);
}
const char* to_string(dg::LambdaPenalty v) {
    return name_of(kLambdaPenalty, v);
}
const char* to_string(integrate::IntegratorKind v) {
    return name_of(kIntegrator, v);
}
const char* to_string(integrate::StaticMode v) {
    return v == integrate::StaticMode::Linear ? "linear" : name_of(kStaticMode, v);
}

} // namespace polycut::scene
