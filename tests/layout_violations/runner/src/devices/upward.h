// devices/ including studies/.
#include "studies/session.h"
