// Kept only for cmd/cmd_eval_shape.cpp (not edited in this change): find_data_dir lives in
// inhap/report/strokes.hpp now. Include that instead and delete this file.
#pragma once

#include "inhap/report/strokes.hpp"

namespace inhap::demo {
using report::find_data_dir;
}  // namespace inhap::demo
