// The one file of the CLI tests compiled with this build's paths and commit (tests/CMakeLists.txt):
// a clone in another folder, or a new commit, recompiles it alone, and ccache serves every other
// test file from an earlier clone's objects.
#include "fscil_build_info.h"
#include "tests/fscil-bench/cli_support.h"

namespace fscil {

std::string built_program() { return FSCIL_BENCH_EXECUTABLE; }
std::filesystem::path source_folder() { return FSCIL_SOURCE_DIR; }
std::string built_version() { return FSCIL_VERSION; }
std::string built_commit() { return FSCIL_SOURCE_COMMIT; }

}  // namespace fscil
