// G-code writing for a large plate: 10 layers of 300 m of path each (1 mm segments, wavy lines at
// 0.2 mm spacing over 250 x 240 mm), on the paper's printer. Reports the time to write (which
// includes the safety check), to check alone and to estimate the print time, with the G-code size.
#include <benchmark/benchmark.h>

#include <cmath>

#include "gcode/estimate.h"
#include "gcode/gcode_check.h"
#include "gcode/gcode_writer.h"

namespace flatmorph {
namespace {

Toolpath large_toolpath() {
  Toolpath toolpath;
  constexpr int kLayers = 10;
  constexpr int kLines = 1200;    // x 250 mm = 300 m per layer
  constexpr int kSegments = 250;  // 1 mm each
  for (int k = 0; k < kLayers; ++k) {
    ToolpathLayer layer;
    layer.height = 0.08;
    layer.z = 0.08 * (k + 1);
    for (int i = 0; i < kLines; ++i) {
      PathPolyline path;
      path.points.resize(kSegments + 1, 3);
      for (int s = 0; s <= kSegments; ++s) {
        const double x = (i % 2 ? kSegments - s : s) * 1.0;
        path.points.row(s) << x, 0.2 * i + 0.05 * std::sin(x / 5 + k), layer.z;
      }
      SegmentStyle style;
      style.width = 0.4;
      style.layer_height = 0.08;
      style.feed_rate = 0;
      path.segments.assign(kSegments, style);
      layer.paths.push_back(std::move(path));
    }
    toolpath.layers.push_back(std::move(layer));
  }
  return toolpath;
}

const Toolpath& toolpath() {
  static const Toolpath t = large_toolpath();
  return t;
}

void BM_WriteGcode3000m(benchmark::State& state) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Material material = load_material("pla-paper");
  size_t bytes = 0;
  double hours = 0;
  for (auto _ : state) {
    const GcodeResult result = make_gcode(toolpath(), printer, {material});
    bytes = result.text.size();
    hours = result.print_time / 3600;
    benchmark::DoNotOptimize(result.text.data());
  }
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["print_hours"] = hours;
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes));
}
BENCHMARK(BM_WriteGcode3000m)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_CheckGcode3000m(benchmark::State& state) {
  const PrinterProfile printer = load_printer("creality-cr10s-pro");
  const Material material = load_material("pla-paper");
  const std::string text = make_gcode(toolpath(), printer, {material}).text;
  for (auto _ : state) {
    benchmark::DoNotOptimize(check_gcode(text, printer, {material}).size());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(text.size()));
}
BENCHMARK(BM_CheckGcode3000m)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_EstimateTime3M(benchmark::State& state) {
  // 3 million 1 mm moves through 10-degree corners.
  std::vector<Motion> motions(3'000'000);
  for (size_t i = 0; i < motions.size(); ++i) {
    const double a = (i % 2 ? 5.0 : -5.0) * 3.14159265358979 / 180;
    motions[i].delta = Eigen::Vector3d(std::cos(a), std::sin(a), 0);
    motions[i].e = 0.013;
    motions[i].speed = 30;
  }
  const MotionLimits limits = motion_limits(load_printer("creality-cr10s-pro"));
  for (auto _ : state) benchmark::DoNotOptimize(estimate_time(motions, limits));
}
BENCHMARK(BM_EstimateTime3M)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace flatmorph
