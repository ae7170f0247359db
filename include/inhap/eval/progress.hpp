// eval::Progress is the library-wide inhap::Progress (core/progress.hpp), named here because the
// experiments' options structs were written against it.
#pragma once

#include "inhap/core/progress.hpp"

namespace inhap::eval {

using inhap::Progress;

}  // namespace inhap::eval
