// The table of fuzz targets.
#include "fuzz_targets.h"

#include <array>

namespace burrlab::fuzz {

std::span<const Target> Targets() {
  // max_len: a few times the largest seed, so mutations can grow inputs
  // without the run spending its time on megabytes.
  static constexpr std::array<Target, 12> kTargets = {{
      {"protocol", &FuzzProtocol, 8192},
      {"station", &FuzzStation, 4096},
      {"station_script", &FuzzStationScript, 4096},
      {"material", &FuzzMaterial, 4096},
      {"nrrd", &FuzzNrrd, 4096},
      {"measured", &FuzzMeasured, 4096},
      {"traces", &FuzzTraces, 4096},
      {"psychometric", &FuzzPsychometric, 4096},
      {"beh_tsv", &FuzzBehTsv, 4096},
      {"participants", &FuzzParticipants, 4096},
      {"physio_sidecar", &FuzzPhysioSidecar, 4096},
      {"physio_rows", &FuzzPhysioRows, 4096},
  }};
  return kTargets;
}

}  // namespace burrlab::fuzz
