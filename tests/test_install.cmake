# ctest install_and_use_package: installs the build tree into a temporary prefix, then configures,
# builds and runs examples/outside against the installed package (find_package(sphib)).
# Arguments: -DBUILD_DIR -DSOURCE_DIR -DWORK_DIR -DGENERATOR, and the build's -DCXX_FLAGS and
# -DBUILD_TYPE (a sanitizer build's library needs the same flags in the program that links it);
# with -DPYTHON and -DPYTHON_DIR (the module's place under the prefix) the installed module is imported.
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "test_install.cmake: -D${v}=... is required")
  endif()
endforeach()

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ok")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f include/sphib/coupling/simulation.hpp include/sphib/sphib_version.hpp bin/sphib)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "install: ${prefix}/${f} is missing")
  endif()
endforeach()
file(GLOB config ${prefix}/lib*/cmake/sphib/sphibConfig.cmake ${prefix}/lib/*/cmake/sphib/sphibConfig.cmake)
if(NOT config)
  message(FATAL_ERROR "install: no lib/cmake/sphib/sphibConfig.cmake under ${prefix}")
endif()
# Every installed header compiles against the installed tree alone: a public header that included a
# private (not installed) one would fail here.
file(GLOB_RECURSE headers RELATIVE ${prefix}/include ${prefix}/include/sphib/*.hpp)
list(LENGTH headers n_headers)
message(STATUS "installed headers: ${n_headers}")
set(all_headers "")
foreach(h ${headers})
  string(APPEND all_headers "#include <${h}>\n")
endforeach()
file(WRITE ${WORK_DIR}/headers/all.cpp "${all_headers}int main() { return 0; }\n")
file(WRITE ${WORK_DIR}/headers/CMakeLists.txt "cmake_minimum_required(VERSION 3.18)\nproject(all_headers LANGUAGES CXX)\n"
     "set(CMAKE_CXX_STANDARD 17)\nfind_package(sphib REQUIRED)\nadd_executable(all_headers all.cpp)\n"
     "target_link_libraries(all_headers PRIVATE sphib::sphib)\n")
step("configure a program including every installed header" ${CMAKE_COMMAND} -S ${WORK_DIR}/headers
     -B ${WORK_DIR}/headers/build -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix} "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}"
     "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
step("build it" ${CMAKE_COMMAND} --build ${WORK_DIR}/headers/build)
step("configure examples/outside" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/outside -B ${WORK_DIR}/build
     -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix} "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
step("build examples/outside" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
step("run examples/outside" ${WORK_DIR}/build/outside)
message(STATUS "${step_output}")
step("installed sphib --version" ${prefix}/bin/sphib --version)
message(STATUS "${step_output}")
if(DEFINED PYTHON)
  step("import the installed module" ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_DIR}
       ${PYTHON} -c "import sphib\nprint(sphib.__file__, sphib.__version__)")  # no ';': CMake splits lists at it
  if(NOT step_output MATCHES "^${prefix}/${PYTHON_DIR}/sphib")
    message(FATAL_ERROR "import sphib found ${step_output}, not the installed module under ${prefix}/${PYTHON_DIR}")
  endif()
  message(STATUS "${step_output}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
