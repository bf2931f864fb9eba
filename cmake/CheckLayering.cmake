# Checks the layout rules of README.md ("Layout") on the source tree (run as a ctest
# with -P):
#  - each library folder includes only public headers of the folders it may depend on;
#  - inside analysis/, the psychophysics part does not include the model-gap layer
#    (analysis/include/burrlab/analysis/model_gap/, analysis/src/model_gap/): the model
#    gap depends on analysis, not the reverse;
#  - main() appears only in runner/.
# Usage: cmake -DSOURCE_DIR=<repo> -P CheckLayering.cmake
set(allowed_sim sim)
set(allowed_results_schema results_schema)
set(allowed_stimuli stimuli sim results_schema)
set(allowed_protocols protocols stimuli sim results_schema)
set(allowed_analysis analysis results_schema sim)
set(allowed_runner runner protocols stimuli sim analysis results_schema)
set(failures "")
foreach(folder sim results_schema stimuli protocols analysis runner)
  file(GLOB_RECURSE files "${SOURCE_DIR}/${folder}/*.h" "${SOURCE_DIR}/${folder}/*.cc")
  foreach(file ${files})
    file(STRINGS "${file}" includes REGEX "^#include \"burrlab/[a-z_]+/")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"burrlab/([a-z_]+)/.*" "\\1" target "${line}")
      list(FIND allowed_${folder} "${target}" found)
      if(found EQUAL -1)
        list(APPEND failures "${file}: ${folder}/ may not include burrlab/${target}/")
      endif()
    endforeach()
    file(RELATIVE_PATH relative "${SOURCE_DIR}" "${file}")
    if(folder STREQUAL "analysis" AND
       NOT relative MATCHES "^analysis/(src|include/burrlab/analysis)/model_gap/")
      file(STRINGS "${file}" model_gap_includes
           REGEX "^#include \"(burrlab/analysis/)?model_gap/")
      if(model_gap_includes)
        list(APPEND failures "${file}: analysis/ outside model_gap/ may not include model_gap/")
      endif()
    endif()
    if(NOT folder STREQUAL "runner")
      file(STRINGS "${file}" mains REGEX "^int main\\(")
      if(mains)
        list(APPEND failures "${file}: main() belongs in runner/ only")
      endif()
    endif()
  endforeach()
endforeach()
if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "layering violations:\n${text}")
endif()
message(STATUS "layering: ok")
