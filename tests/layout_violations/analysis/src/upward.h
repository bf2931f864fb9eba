// burrlab::analysis outside the model-gap layer including the simulator.
#include "burrlab/sim/descent.h"
