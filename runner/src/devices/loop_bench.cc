// The haptic-loop benchmark.
#include "devices/loop_bench.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "burrlab/sim/phantoms.h"
#include "burrlab/sim/step.h"
#include "burrlab/stimuli/materials.h"
#include "devices/sim_force_source.h"
#include "devices/simulated_device.h"

namespace burrlab::runner {

Result<LoopBenchResult> RunLoopBench(const LoopBenchOptions& options) {
  if (!(options.seconds > 0.0) || !(options.rate_hz > 0.0)) {
    return Error{fmt::format(
        "loop bench: seconds and rate_hz must be positive, got {} and {}",
        options.seconds, options.rate_hz)};
  }
  Result<stimuli::MaterialSet> set =
      stimuli::LoadBuiltinMaterial(options.material);
  if (!set.ok()) return set.error();
  sim::Model model;
  model.material = set->material;
  model.radius_mm = options.radius_mm;
  model.dt_s = 1.0 / options.rate_hz;
  if (Status s = model.Validate(); !s.ok()) return s.error();

  // A 19.2 mm cube of 0.3 mm voxels, solid below its middle plane.
  sim::PhantomGrid grid;
  grid.nx = grid.ny = grid.nz = 64;
  const double middle_mm = 0.5 * grid.nx * grid.voxel_mm;
  Result<sim::Volume> volume =
      sim::MakeHalfSpace(grid, glm::dvec3(middle_mm), {0.0, 0.0, 1.0});
  if (!volume.ok()) return volume.error();
  Result<sim::State> state = sim::State::Create(model, std::move(*volume), 1);
  if (!state.ok()) return state.error();

  // The burr circles (radius 4 mm, one turn every 2 s) a quarter of its
  // radius deep.
  LoopBenchResult result;
  result.options = options;
  result.planned_ticks = static_cast<std::int64_t>(
      std::llround(options.seconds * options.rate_hz));
  SimulatedDeviceOptions device_options;
  device_options.positions_mm.reserve(
      static_cast<std::size_t>(result.planned_ticks));
  const double depth_z_mm =
      middle_mm + options.radius_mm - 0.25 * options.radius_mm;
  for (std::int64_t k = 0; k < result.planned_ticks; ++k) {
    const double angle =
        std::numbers::pi * static_cast<double>(k) / options.rate_hz;
    device_options.positions_mm.emplace_back(middle_mm + 4.0 * std::cos(angle),
                                             middle_mm + 4.0 * std::sin(angle),
                                             depth_z_mm);
  }
  SimulatedDevice device(std::move(device_options));
  result.max_force_n = device.spec().max_force_n;
  SimForceSource source(model, &*state, glm::dvec3(0.0),
                        glm::dvec3(0.0, 0.0, 1000.0));
  MonotonicClock clock;
  LoopOptions loop_options;
  loop_options.rate_hz = options.rate_hz;
  loop_options.realtime = options.realtime;
  loop_options.max_samples = static_cast<std::size_t>(result.planned_ticks);
  HapticLoop loop(&device, &source, &clock, loop_options);
  if (Status s = loop.Start(result.planned_ticks); !s.ok()) return s.error();
  loop.Wait();
  if (!loop.fault().ok()) {
    return Error{fmt::format("loop bench: the simulated device failed: {}",
                             loop.fault().reason)};
  }
  result.stats = loop.Stats();
  result.counters = loop.counters();
  result.realtime = loop.realtime();
  return result;
}

}  // namespace burrlab::runner
