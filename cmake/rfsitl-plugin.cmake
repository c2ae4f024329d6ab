# rfsitl_add_plugin(<name> <sources>...): an rfsitl plugin, <name>.so, built
# against rfsitl::rfsitl (librfsitl) with the flags of the rfsitl it was found
# in (rfsitl::plugin). Only its entry points are exported (RFSITL_PLUGIN in
# rfsitl/registry/plugin.hpp); put it in RFSITL_PLUGIN_PATH or in
# RFSITL_PLUGIN_DIR, the installed rfsitl's plugin folder. Shared by the
# build-tree and the installed package configs.
function(rfsitl_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  target_link_libraries(${name} PRIVATE rfsitl::plugin)
  set_target_properties(${name} PROPERTIES PREFIX "" CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
endfunction()
