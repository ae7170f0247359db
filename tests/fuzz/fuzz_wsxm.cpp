#include "fuzz_common.hpp"
#include "inhap/geometry/heightmap.hpp"
INHAP_FUZZ_FILE_READER("top", inhap::read_wsxm_top)
