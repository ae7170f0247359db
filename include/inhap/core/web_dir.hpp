// Where inhap's web assets live (the demo report's template and the studio's page, with the
// JavaScript libraries npm installs beside them): `web/` of the source tree or `share/inhap/web`
// of an installation.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace inhap {

/// Where a folder `name` of inhap's is looked for: `name` and `share/inhap/name` beside the
/// running program and in up to four folders above it, then `name` in the working directory.
std::vector<std::filesystem::path> beside_program(const std::string& name);

/// The web folder: `given` (a --web-dir flag) when non-empty, else $INHAP_WEB_DIR, else `web/` or
/// `share/inhap/web` beside the running program or up to four folders above it, else ./web. Returns
/// the first candidate for which `has(dir)` holds; throws inhap::Error naming `what` (e.g. "the
/// studio page web/studio/index.html") and where it looked.
std::string find_web_dir(const std::string& given,
                         const std::function<bool(const std::filesystem::path&)>& has,
                         const std::string& what);

}  // namespace inhap
