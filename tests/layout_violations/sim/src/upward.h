// The simulator including a library above it.
#include "burrlab/stimuli/materials.h"
