#include "fuzz_common.hpp"
#include "inhap/geometry/heightmap.hpp"
INHAP_FUZZ_FILE_READER("csv", inhap::read_grid)
