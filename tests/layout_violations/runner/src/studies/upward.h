// studies/ including the layers it may not use.
#include "cli/flags.h"
#include "devices/haptic_loop.h"
#include "station/window.h"
