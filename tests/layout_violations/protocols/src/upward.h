// protocols including the journal: the engine records nothing itself (the
// runner writes what it decides), so it may not depend on results_schema.
#include "burrlab/results_schema/journal.h"
