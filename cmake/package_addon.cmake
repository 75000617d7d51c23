# Packs the add-on folder into an installable zip, run from addon/:
#   cmake -DOUTPUT=<zip> -DPLATFORM=<Blender platform, e.g. linux-x64> -DSTAGE=<empty folder> -P package_addon.cmake
# Only what Blender needs goes in: sources, their data tables (*.csv), the manifest (its platforms set to PLATFORM) and the
# compiled module _core (no __pycache__, nothing a developer left in the folder). Two things stay out:
# the evaluation subpackage, a developer's tool (blender_scripts/eval.py, tests) that the add-on never
# imports, and _imageio, whose OpenImageIO would tie the zip to this machine's libraries.
file(GLOB_RECURSE files RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}
     shadecut/*.py shadecut/*.csv shadecut/blender_manifest.toml shadecut/_core.*)
list(FILTER files EXCLUDE REGEX "__pycache__")
list(FILTER files EXCLUDE REGEX "^shadecut/evaluation/")
list(FIND files "shadecut/__init__.py" has_init)
if(has_init EQUAL -1 OR NOT files MATCHES "_core")
  message(FATAL_ERROR "package_addon: run from addon/ after building _core (found: ${files})")
endif()
file(REMOVE_RECURSE ${STAGE})
foreach(path IN LISTS files)
  get_filename_component(folder ${path} DIRECTORY)
  file(COPY ${path} DESTINATION ${STAGE}/${folder})
endforeach()
file(READ shadecut/blender_manifest.toml manifest)
string(REGEX REPLACE "platforms = \\[[^]]*\\]" "platforms = [\"${PLATFORM}\"]" manifest "${manifest}")
file(WRITE ${STAGE}/shadecut/blender_manifest.toml "${manifest}")
file(REMOVE ${OUTPUT})
execute_process(COMMAND ${CMAKE_COMMAND} -E tar cf ${OUTPUT} --format=zip shadecut
                WORKING_DIRECTORY ${STAGE} RESULT_VARIABLE failed)
if(failed)
  message(FATAL_ERROR "package_addon: could not write ${OUTPUT}")
endif()
message(STATUS "Blender add-on: ${OUTPUT}")
