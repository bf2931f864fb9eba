# Checks the layout rules of README.md ("Layout") on the source tree (run as a ctest
# with -P):
#  - each library folder includes only public headers of the folders it may depend on;
#    every folder may include burrlab/base/ (burrlab::base, in sim/base/), which is
#    checked as a folder of its own and includes nothing else of burrlab; sim/ outside
#    base/ includes only sim/ and base/; analysis/ outside model_gap/ (burrlab::analysis)
#    includes no sim/, only its model-gap layer does;
#  - inside analysis/, the psychophysics part does not include the model-gap layer
#    (analysis/include/burrlab/analysis/model_gap/, analysis/src/model_gap/): the model
#    gap depends on analysis, not the reverse;
#  - main() appears only in runner/;
#  - inside runner/src/, the layers include one way (runner/CMakeLists.txt): cli/ may
#    include station/, studies/, devices/; station/ may include studies/ and devices/;
#    studies/ and devices/ include neither each other nor anything above; every layer
#    may include common/, which includes no layer; includes name their layer folder
#    ("studies/session.h"), never "../";
#  - in runner/CMakeLists.txt only the station and devices targets link GLFW, OpenGL,
#    Dear ImGui, hidapi or libusb, and a layer target links only the runner targets
#    its folder may include; in tests/runner/CMakeLists.txt the studies test binary
#    (runner_studies_tests) links no runner target but the studies layer and none of
#    those libraries.
# Usage: cmake -DSOURCE_DIR=<repo> -P CheckLayering.cmake
cmake_minimum_required(VERSION 3.25)
set(allowed_base base)
set(allowed_sim sim base)
set(allowed_results_schema results_schema base)
set(allowed_stimuli stimuli sim results_schema base)
set(allowed_protocols protocols stimuli sim base)
set(allowed_analysis analysis results_schema base)
set(allowed_analysis_model_gap analysis results_schema sim base)
set(allowed_runner runner protocols stimuli sim analysis results_schema base)
# The runner's layers (runner/src/<layer>/) and the layers each may include.
set(runner_layers cli station studies devices common)
set(layer_allowed_cli cli station studies devices common)
set(layer_allowed_station station studies devices common)
set(layer_allowed_studies studies common)
set(layer_allowed_devices devices common)
set(layer_allowed_common common)
# Files of runner/ outside the layers (main.cc, the public burrlab/runner/cli.h).
set(layer_allowed_none "")
# Libraries only the station and devices layers may link (matched in lowercase).
set(device_libraries glfw opengl imgui hidapi libusb)
set(failures "")
foreach(folder sim results_schema stimuli protocols analysis runner)
  file(GLOB_RECURSE files "${SOURCE_DIR}/${folder}/*.h" "${SOURCE_DIR}/${folder}/*.cc")
  foreach(file ${files})
    file(RELATIVE_PATH relative "${SOURCE_DIR}" "${file}")
    # The include rules of the file's folder; sim/base/ and analysis/'s two parts
    # have their own.
    set(checked ${folder})
    set(label "${folder}/")
    if(relative MATCHES "^sim/base/")
      set(checked base)
      set(label "sim/base/")
    elseif(relative MATCHES "^analysis/(src|include/burrlab/analysis)/model_gap/")
      set(checked analysis_model_gap)
    elseif(folder STREQUAL "analysis")
      set(label "analysis/ outside model_gap/")
    endif()
    file(STRINGS "${file}" includes REGEX "^#include \"burrlab/[a-z_]+/")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"burrlab/([a-z_]+)/.*" "\\1" target "${line}")
      list(FIND allowed_${checked} "${target}" found)
      if(found EQUAL -1)
        list(APPEND failures "${file}: ${label} may not include burrlab/${target}/")
      endif()
    endforeach()
    if(folder STREQUAL "analysis" AND
       NOT relative MATCHES "^analysis/(src|include/burrlab/analysis)/model_gap/")
      file(STRINGS "${file}" model_gap_includes
           REGEX "^#include \"(burrlab/analysis/)?model_gap/")
      if(model_gap_includes)
        list(APPEND failures "${file}: analysis/ outside model_gap/ may not include model_gap/")
      endif()
    endif()
    if(folder STREQUAL "runner")
      set(layer none)
      if(relative MATCHES "^runner/src/([a-z_0-9]+)/")
        set(layer ${CMAKE_MATCH_1})
        if(NOT layer IN_LIST runner_layers)
          list(APPEND failures "${file}: runner/src/${layer}/ is not a layer of the runner")
          set(layer none)
        endif()
      endif()
      file(STRINGS "${file}" quoted_includes REGEX "^#include \"[^\"]*\"")
      foreach(line ${quoted_includes})
        string(REGEX REPLACE "^#include \"([^\"]*)\".*" "\\1" header "${line}")
        if(header MATCHES "\\.\\./")
          list(APPEND failures "${file}: includes \"${header}\" (name the layer folder instead)")
        elseif(header MATCHES "^([a-z_0-9]+)/")
          set(target_layer ${CMAKE_MATCH_1})
          if(target_layer IN_LIST runner_layers AND
             NOT target_layer IN_LIST layer_allowed_${layer})
            list(APPEND failures "${file}: runner/src/${layer}/ may not include ${target_layer}/")
          endif()
        endif()
      endforeach()
    endif()
    if(NOT folder STREQUAL "runner")
      file(STRINGS "${file}" mains REGEX "^int main\\(")
      if(mains)
        list(APPEND failures "${file}: main() belongs in runner/ only")
      endif()
    endif()
  endforeach()
endforeach()
# The calls of a CMakeLists.txt that link (comments dropped), as a list of
# "<command>(<arguments>)" texts with the arguments on one line.
function(linking_calls cmake_file out)
  file(READ "${cmake_file}" text)
  string(REGEX REPLACE "#[^\n]*" "" text "${text}")
  string(REGEX REPLACE "[\n\t ]+" " " text "${text}")
  string(REGEX MATCHALL "(burrlab_library|burrlab_test|target_link_libraries) ?\\([^)]*\\)"
         calls "${text}")
  set(${out} "${calls}" PARENT_SCOPE)
endfunction()
# The runner's layer targets: burrlab_library(runner_<layer> ...) and
# target_link_libraries(burrlab_runner_<layer> ...); runner (the cli layer) is burrlab::runner.
if(EXISTS "${SOURCE_DIR}/runner/CMakeLists.txt")
  linking_calls("${SOURCE_DIR}/runner/CMakeLists.txt" calls)
  foreach(call ${calls})
    if(NOT call MATCHES "^[a-z_]+ ?\\( ?(burrlab_)?runner(_[a-z]+)?[ )]")
      continue()
    endif()
    string(REGEX REPLACE "^_" "" layer "${CMAKE_MATCH_2}")
    if(layer STREQUAL "")
      set(layer cli)
    endif()
    string(TOLOWER "${call}" lower)
    if(NOT layer STREQUAL "station" AND NOT layer STREQUAL "devices")
      foreach(library ${device_libraries})
        if(lower MATCHES "${library}")
          list(APPEND failures
               "runner/CMakeLists.txt: the ${layer} layer links ${library} (only station and devices may)")
        endif()
      endforeach()
    endif()
    # What the call links: its arguments after the target's name.
    string(REGEX REPLACE "^[a-z_]+ ?\\( ?[a-z_]+" "" linking "${call}")
    string(REGEX MATCHALL "burrlab(::|_)runner(_[a-z]+)?" linked "${linking}")
    foreach(target ${linked})
      string(REGEX REPLACE "burrlab(::|_)runner_?" "" target_layer "${target}")
      if(target_layer STREQUAL "")
        set(target_layer cli)
      endif()
      if(NOT target_layer IN_LIST layer_allowed_${layer})
        list(APPEND failures
             "runner/CMakeLists.txt: the ${layer} layer links ${target} (it may not use ${target_layer}/)")
      endif()
    endforeach()
  endforeach()
endif()
# The studies tests' binary needs no window and no device.
if(EXISTS "${SOURCE_DIR}/tests/runner/CMakeLists.txt")
  linking_calls("${SOURCE_DIR}/tests/runner/CMakeLists.txt" calls)
  foreach(call ${calls})
    if(NOT call MATCHES "^[a-z_]+ ?\\( ?runner_studies_tests[ )]")
      continue()
    endif()
    string(TOLOWER "${call}" lower)
    foreach(library ${device_libraries})
      if(lower MATCHES "${library}")
        list(APPEND failures "tests/runner/CMakeLists.txt: runner_studies_tests links ${library}")
      endif()
    endforeach()
    string(REGEX MATCHALL "burrlab(::|_)runner(_[a-z]+)?" linked "${call}")
    foreach(target ${linked})
      if(NOT target MATCHES "runner_studies$")
        list(APPEND failures "tests/runner/CMakeLists.txt: runner_studies_tests links ${target}")
      endif()
    endforeach()
  endforeach()
endif()
if(failures)
  # One line each, unwrapped (FATAL_ERROR wraps its text), then the failure.
  list(JOIN failures "\n" text)
  message("layering violations:\n${text}")
  list(LENGTH failures count)
  message(FATAL_ERROR "${count} layering violations (listed above)")
endif()
message(STATUS "layering: ok")
