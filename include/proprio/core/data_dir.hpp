#pragma once
// Where proprio's shipped data lives (arm models, the object catalogue, scenarios): the source
// tree's data/ directory, installed as <prefix>/share/proprio. Found at run time, never through a
// path compiled into the libraries from the source tree.

#include <filesystem>

namespace proprio::core {

/// The data directory (the one that holds models/, objects/ and scenarios/), first of:
/// 1. $PROPRIO_DATA_DIR when it is set and not empty (it must then be a directory);
/// 2. <directory of the running program>/../share/proprio, as laid out by `cmake --install` (and,
///    through a link, in the build tree, so that build/app/proprio finds the source tree's data/);
/// 3. the installation's data directory configured at build time
/// (CMAKE_INSTALL_FULL_DATADIR/proprio). A candidate counts only when it holds models/. Throws
/// Error naming what was tried otherwise.
std::filesystem::path data_directory();

}  // namespace proprio::core
