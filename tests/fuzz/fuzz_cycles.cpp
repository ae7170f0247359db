#include "fuzz_common.hpp"
#include "inhap/friction/cycles_io.hpp"
INHAP_FUZZ_FILE_READER("csv", inhap::friction::read_cycles_csv)
