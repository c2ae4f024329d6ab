#pragma once
/// Out-of-tree components: a shared library (a plugin) that registers PHYs,
/// MACs, channel stages, position sources or mobility models at start, as the
/// built-ins register themselves. A plugin's one source file that says
///
///   #include "rfsitl/registry/plugin.hpp"
///   #include "rfsitl/registry/channel_stage_registry.hpp"
///   static void register_mine() {
///     rfsitl::channel::channel_stage_registry().add(my_stage_component());
///   }
///   RFSITL_PLUGIN(register_mine)
///
/// is loaded by every rfsitl program from the folders of RFSITL_PLUGIN_PATH
/// (colon-separated) and the installed plugin folder (plugin_loader.hpp).
/// Before its registration runs, the loader compares the plugin's ABI tag
/// with its own: a plugin built against another rfsitl, another C++ ABI or
/// with other sanitizers is refused with a message that says so, instead of
/// crashing in a mismatched call.
///
/// The plugin reaches the engine's symbols through the program that loads it
/// (the `rfsitl` executable exports them), so it links nothing of rfsitl's.
#include "rfsitl/version.hpp"

#define RFSITL_PLUGIN_STRINGIFY2(x) #x
#define RFSITL_PLUGIN_STRINGIFY(x) RFSITL_PLUGIN_STRINGIFY2(x)

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#if defined(__SANITIZE_ADDRESS__)
#define RFSITL_PLUGIN_SANITIZER " asan"
#else
#define RFSITL_PLUGIN_SANITIZER " tsan"
#endif
#else
#define RFSITL_PLUGIN_SANITIZER ""
#endif

/// What must match between a plugin and the program loading it: rfsitl's
/// version (its interfaces may change with any release), the C++ ABI of the
/// compiler and of libstdc++'s strings, and the sanitizers (an ASan program
/// and a plain plugin lay out and check memory differently).
#define RFSITL_PLUGIN_ABI_TAG                                                         \
  "rfsitl " RFSITL_VERSION " c++abi " RFSITL_PLUGIN_STRINGIFY(                        \
      __GXX_ABI_VERSION) " cxx11abi " RFSITL_PLUGIN_STRINGIFY(_GLIBCXX_USE_CXX11_ABI) \
      RFSITL_PLUGIN_SANITIZER

/// Declares the plugin's two entry points: its ABI tag, and `register_fn`
/// (a `void()` that adds the plugin's components to the registries; it may
/// throw std::exception, which the loader reports).
#define RFSITL_PLUGIN(register_fn)                                                    \
  extern "C" __attribute__((visibility("default"))) const char* rfsitl_plugin_abi() { \
    return RFSITL_PLUGIN_ABI_TAG;                                                     \
  }                                                                                   \
  extern "C" __attribute__((visibility("default"))) void rfsitl_plugin_register() {   \
    register_fn();                                                                    \
  }
