// common/ including a layer.
#include "devices/device.h"
