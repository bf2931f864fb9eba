// What the subject window shows of the simulator, and how it gets there
// without blocking the haptic loop (README.md, "Haptic devices and the 1 kHz
// loop"; dissertation ch. 11): the loop side keeps a height map of the material
// block up to date around the burr and publishes it with the burr position and
// force into a triple buffer; the window takes the newest one at its own rate.
// Publish and the height-map update allocate nothing, take no lock and throw
// nothing.
#ifndef BURRLAB_RUNNER_STATION_SURFACE_SNAPSHOT_H_
#define BURRLAB_RUNNER_STATION_SURFACE_SNAPSHOT_H_

#include <array>
#include <atomic>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "burrlab/sim/volume.h"

namespace burrlab::runner {

// Material per column of the volume: height_mm[j * nx + i] is the solid
// equivalent thickness of column (i, j) (sum of occupancy / 255 times the
// voxel size), so erosion lowers it smoothly.
struct HeightMap {
  int nx = 0;
  int ny = 0;
  double cell_mm = 0.3;  // column width = voxel size
  double top_mm = 0.0;   // height of the volume (nz times the voxel size)
  std::vector<float> height_mm;

  // A zero map of the volume's footprint (allocates).
  static HeightMap For(const sim::Volume& volume);
  float At(int i, int j) const {
    return height_mm[static_cast<std::size_t>(j) * nx + i];
  }
};

// Recomputes the columns whose centres lie within `radius_mm` of `centre_mm`
// (x, y only; the whole map when radius_mm is negative). `map` must come from
// HeightMap::For(volume). Allocates nothing.
void UpdateHeightMap(const sim::Volume& volume, const glm::dvec3& centre_mm,
                     double radius_mm, HeightMap* map) noexcept;

// One frame's worth of the simulator for the window.
struct SurfaceSnapshot {
  HeightMap surface;
  glm::dvec3 burr_mm{0.0};  // burr centre in the volume frame
  double burr_radius_mm = 0.0;
  glm::dvec3 force_n{0.0};  // force sent to the device
  std::int64_t tick = 0;    // haptic tick that produced it
};

// Single producer (the loop), single consumer (the window), three slots: the
// producer never waits for the consumer and the consumer always gets the
// newest complete snapshot.
class SnapshotExchange {
 public:
  // Every slot gets the shape of `shape` (its height map sizes).
  explicit SnapshotExchange(const SurfaceSnapshot& shape);

  // The slot to fill (producer only); its contents are stale.
  SurfaceSnapshot& WriteSlot() noexcept { return slots_[write_]; }
  // Makes the write slot the newest snapshot (producer only).
  void Publish() noexcept;
  // Copies `snapshot` into the write slot and publishes it; the height maps
  // must have the same size. Allocates nothing.
  void Publish(const SurfaceSnapshot& snapshot) noexcept;
  // The newest published snapshot, or nullptr when nothing new came since the
  // last call (consumer only). Valid until the next call.
  const SurfaceSnapshot* TakeNewest() noexcept;

 private:
  static constexpr std::uint8_t kFresh = 4;  // flag bit in middle_
  std::array<SurfaceSnapshot, 3> slots_;
  int write_ = 0;
  int read_ = 2;
  std::atomic<std::uint8_t> middle_{1};  // slot index | kFresh
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_SURFACE_SNAPSHOT_H_
