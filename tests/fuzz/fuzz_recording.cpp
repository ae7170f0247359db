#include "fuzz_common.hpp"
#include "inhap/core/csv.hpp"
INHAP_FUZZ_FILE_READER("csv", inhap::read_recording)
