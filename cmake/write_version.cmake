# Writes OUT (a .cpp defining tumble::kVersion and tumble::kGitHash) from the source tree's
# current commit. Run at every build (cmake -P, from the tumble_version_stamp target), not only at
# configure time: a configure-time hash went stale after the next commit, and every result file of
# an incremental build named a commit it was not built from. OUT is rewritten only when its text
# changes, so an unchanged tree recompiles nothing. "-dirty": tracked files differ from HEAD.
# usage: cmake -DSRC=<source dir> -DOUT=<file> -DVERSION=<x.y.z> -P write_version.cmake
execute_process(COMMAND git rev-parse --short HEAD WORKING_DIRECTORY "${SRC}"
                OUTPUT_VARIABLE hash OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT hash)
  set(hash "unknown")
else()
  execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY "${SRC}"
                  RESULT_VARIABLE dirty OUTPUT_QUIET ERROR_QUIET)
  if(NOT dirty EQUAL 0)
    string(APPEND hash "-dirty")
  endif()
endif()
set(text "// Generated at build time by cmake/write_version.cmake: provenance for every HDF5 file.
#include \"base/version.hpp\"
namespace tumble {
const char* const kVersion = \"${VERSION}\";
const char* const kGitHash = \"${hash}\";
}  // namespace tumble
")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
