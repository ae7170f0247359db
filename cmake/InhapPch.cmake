# Precompiled headers (INHAP_PCH, default ON): the heavy, stable third-party and standard headers
# that most translation units parse (Eigen's Core, nlohmann/json, fmt, CLI11, GoogleTest and the
# standard library), never the project's own headers (they change) and never CGAL (only five
# translation units use it; a PCH of it would slow every other unit down). GCC reads a .gch in a
# fraction of the time it takes to parse these headers (docs/architecture.md, "Build time").
#
# A precompiled header is used only when the unit's compile flags match the flags it was built
# with, so each library target builds its own; the test programs (identical flags) share one,
# and so do the benchmark programs. With INHAP_PCH=OFF every unit includes what it uses, as
# before: that build catches a missing #include the PCH would hide.

set(INHAP_PCH_STD
  <algorithm> <array> <atomic> <chrono> <cmath> <cstddef> <cstdint> <cstdio> <cstdlib> <cstring>
  <filesystem> <fstream> <functional> <limits> <map> <memory> <numbers> <numeric> <optional>
  <span> <sstream> <string> <string_view> <thread> <unordered_map> <utility> <vector>)
set(INHAP_PCH_THIRD_PARTY <Eigen/Core> <fmt/format.h> <nlohmann/json.hpp>)

# inhap_pch(<target> [extra headers...]): a PCH of its own for <target>.
function(inhap_pch target)
  if(INHAP_PCH)
    target_precompile_headers(${target} PRIVATE ${INHAP_PCH_STD} ${INHAP_PCH_THIRD_PARTY} ${ARGN})
  endif()
endfunction()

# inhap_pch_shared(<group> <target> [extra headers...]): the first target of <group> builds the
# PCH, the later ones reuse it (their compile flags must be the same).
function(inhap_pch_shared group target)
  if(NOT INHAP_PCH)
    return()
  endif()
  get_property(_first GLOBAL PROPERTY INHAP_PCH_GROUP_${group})
  if(_first)
    target_precompile_headers(${target} REUSE_FROM ${_first})
  else()
    target_precompile_headers(${target} PRIVATE ${INHAP_PCH_STD} ${INHAP_PCH_THIRD_PARTY} ${ARGN})
    set_property(GLOBAL PROPERTY INHAP_PCH_GROUP_${group} ${target})
  endif()
endfunction()
