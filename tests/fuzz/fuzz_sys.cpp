#include "fuzz_common.hpp"
#include "inhap/friction/sys_model.hpp"
INHAP_FUZZ_FILE_READER("json", inhap::friction::read_sys_json)
