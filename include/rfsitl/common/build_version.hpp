#pragma once
/// The one version this build reports (`rfsitl --version`, the summary JSON,
/// rfsitl_build_info in /metrics): `git describe` of the clone it was built
/// from (e.g. 0.1.0-g6fc0084-dirty), or the project version (version.hpp's
/// RFSITL_VERSION) when built outside a clone, as a package is.
///
/// RFSITL_VERSION, not this, is what plugins are checked against (their ABI
/// tag): a rebuild at another commit of the same release keeps its plugins.

namespace rfsitl {

/// The version string; static storage, never null.
const char* build_version();

}  // namespace rfsitl
