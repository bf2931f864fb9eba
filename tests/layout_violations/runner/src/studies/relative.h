// A layer reached with "../" instead of by name.
#include "../devices/device.h"
