// scene_writer.hpp — a validated Scene back to TOML (Scene::effective_toml): every key with
// the value the run used, defaults filled in, numbers in their shortest exact form. Every
// output records it (style guide 3.7). Also the TOML spelling of the scene's enumerators,
// shared with the reader so that what is written reads back.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/config/table_reader.hpp"

#include <string>

namespace cdpowder::detail {

inline constexpr EnumNames<CohesionRule, 2> kCohesionRuleNames = {
    {{"graph", CohesionRule::Graph}, {"history", CohesionRule::History}}};
inline constexpr EnumNames<StoppingRule, 2> kStoppingRuleNames = {
    {{"residual", StoppingRule::Residual}, {"relative_change", StoppingRule::RelativeChange}}};
inline constexpr EnumNames<VtkFormat, 2> kVtkFormatNames = {
    {{"ascii", VtkFormat::Ascii}, {"binary", VtkFormat::Binary}}};
inline constexpr EnumNames<CaptureRule, 2> kCaptureRuleNames = {
    {{"centre_distance", CaptureRule::CentreDistance}, {"surface_gap", CaptureRule::SurfaceGap}}};
inline constexpr EnumNames<VisitOrder, 3> kVisitOrderNames = {
    {{"random_each_step", VisitOrder::RandomEachStep},
     {"random_each_sweep", VisitOrder::RandomEachSweep},
     {"fixed", VisitOrder::Fixed}}};
inline constexpr EnumNames<SweepKernel, 2> kSweepKernelNames = {
    {{"scalar", SweepKernel::Scalar}, {"coloured", SweepKernel::Coloured}}};

/// The validated scene as TOML: every key with its effective value. Unset optional keys
/// (piston.pressure, piston.force, piston.height) are left out: TOML has no null.
std::string write_effective_toml(const Scene& s);

}  // namespace cdpowder::detail
