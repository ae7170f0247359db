# Unity (jumbo) build (INHAP_UNITY): CMake compiles each target's sources in batches of
# INHAP_UNITY_BATCH_SIZE, each batch one generated translation unit in the build folder
# (<target>.dir/Unity/unity_<n>_cxx.cxx) that #includes the sources. The heavy headers (Eigen,
# CGAL, fmt, nlohmann/json, CLI11, GoogleTest) are then parsed, and their templates instantiated
# and optimised, once per batch instead of once per source. Works with INHAP_PCH (the PCH is
# force-included into each batch).
#
# What it asks of the sources: names at namespace scope in a .cpp (anonymous namespaces, static
# functions, using-directives, macros) must not clash with those of another .cpp of the same
# target; file-local helpers therefore carry a file-specific name or namespace. A source with
# its own compile options (e.g. src/geometry/mesh_index.cpp, -ffp-contract=off) is compiled on
# its own (CMake never batches a source with source-level options); one that cannot be merged
# gets SKIP_UNITY_BUILD_INCLUSION with the reason beside it. A build with INHAP_UNITY=OFF
# compiles every source on its own and catches a source that relies on a header another source
# of its batch included.

set(INHAP_UNITY_BATCH_SIZE 8 CACHE STRING "Sources per unity translation unit (INHAP_UNITY)")

# inhap_unity(<target>...): batch the sources of each <target> when INHAP_UNITY is ON.
function(inhap_unity)
  if(NOT INHAP_UNITY)
    return()
  endif()
  foreach(t IN LISTS ARGN)
    set_target_properties(${t} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE BATCH
                                          UNITY_BUILD_BATCH_SIZE ${INHAP_UNITY_BATCH_SIZE})
    # GCC warns when a class with external linkage defined outside the main file has a member
    # of a type from an anonymous namespace (meant for headers); in a batch every source is
    # "outside the main file", so a source's private Impl holding its file-local types would
    # warn although it is still defined in one translation unit only.
    target_compile_options(${t} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
  endforeach()
endfunction()
