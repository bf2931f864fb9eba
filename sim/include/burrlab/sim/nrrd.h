// Loading CT-derived volumes from NRRD files (raw and gzip encodings, 8- and
// 16-bit, signed or unsigned, little or big endian) with a threshold or a
// linear intensity-to-occupancy mapping. NRRD files are untrusted input: every
// header field is checked and sizes are bounded before allocation.
#ifndef BURRLAB_SIM_NRRD_H_
#define BURRLAB_SIM_NRRD_H_

#include <string>
#include <string_view>

#include "burrlab/base/result.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {

// How CT intensities become occupancy 0..255.
struct IntensityMapping {
  enum class Kind { kThreshold, kLinear };
  Kind kind = Kind::kThreshold;
  double threshold = 0.5;  // kThreshold: intensity >= threshold -> 255, else 0
  double low = 0.0;        // kLinear: intensity <= low -> 0
  double high = 255.0;  // kLinear: intensity >= high -> 255, linear in between
};

// Parses an NRRD file held in memory; `name` is used in error messages only.
// Voxels must be isotropic (spacings equal within 1 %); the voxel size comes
// from `spacings` or `space directions` (default 0.3 mm when neither is given).
Result<Volume> ParseNrrd(std::string_view name, std::string_view bytes,
                         const IntensityMapping& mapping);

// Reads and parses an NRRD file (attached header; detached data files are
// refused).
Result<Volume> LoadNrrd(const std::string& path,
                        const IntensityMapping& mapping);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_NRRD_H_
