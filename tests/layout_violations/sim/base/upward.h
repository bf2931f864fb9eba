// burrlab::base including the simulator it sits under.
#include "burrlab/sim/volume.h"
