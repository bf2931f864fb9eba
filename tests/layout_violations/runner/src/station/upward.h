// station/ including cli/.
#include "cli/command_table.h"
