#include "fuzz_common.hpp"
#include "inhap/geometry/volume.hpp"
INHAP_FUZZ_FILE_READER("nrrd", inhap::read_nrrd)
