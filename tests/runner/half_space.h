// The runner tests' block: solid below z = 9.6 mm in a 19.2 mm cube of 0.3 mm
// voxels.
#ifndef BURRLAB_TESTS_RUNNER_HALF_SPACE_H_
#define BURRLAB_TESTS_RUNNER_HALF_SPACE_H_

#include "burrlab/sim/phantoms.h"
#include "burrlab/sim/volume.h"

namespace burrlab::runner {

inline sim::Volume HalfSpace() {
  sim::PhantomGrid grid;
  grid.nx = grid.ny = grid.nz = 64;
  return sim::MakeHalfSpace(grid, {9.6, 9.6, 9.6}, {0.0, 0.0, 1.0}).value();
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_HALF_SPACE_H_
