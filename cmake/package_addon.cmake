# Packs the add-on folder into an installable zip: cmake -DOUTPUT=<zip> -P package_addon.cmake,
# run from addon/. Only what Blender needs goes in: sources, the manifest and the compiled module
# (no __pycache__, nothing a developer left in the folder). The evaluation subpackage is a developer's
# tool (blender_scripts/eval.py, tests) that the add-on never imports: it stays out of the zip.
file(GLOB_RECURSE files RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}
     shadecut/*.py shadecut/blender_manifest.toml shadecut/_core*.so)
list(FILTER files EXCLUDE REGEX "__pycache__")
list(FILTER files EXCLUDE REGEX "^shadecut/evaluation/")
list(FIND files "shadecut/__init__.py" has_init)
if(has_init EQUAL -1 OR NOT files MATCHES "_core")
  message(FATAL_ERROR "package_addon: run from addon/ after building _core (found: ${files})")
endif()
file(REMOVE ${OUTPUT})
file(ARCHIVE_CREATE OUTPUT ${OUTPUT} PATHS ${files} FORMAT zip)
message(STATUS "Blender add-on: ${OUTPUT}")
