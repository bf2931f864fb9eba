// results_schema, a root of the graph, including the simulator.
#include "burrlab/sim/volume.h"
