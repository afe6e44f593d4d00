# The package_consumer test (tests/CMakeLists.txt), run with cmake -P:
#   install the build tree into WORK_DIR/prefix, configure + build + run tests/consumer against it,
#   and check that the version file refuses find_package(lowpair 0.2), (lowpair 0.4) and (lowpair 1.0).
# Inputs (-D): BUILD_DIR, CONSUMER_DIR, WORK_DIR, GENERATOR, CXX_COMPILER, CONFIG (may be empty),
#              INSTALL_LIBDIR, INSTALL_INCLUDEDIR.
cmake_minimum_required(VERSION 3.22)

foreach(var BUILD_DIR CONSUMER_DIR WORK_DIR GENERATOR CXX_COMPILER INSTALL_LIBDIR INSTALL_INCLUDEDIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run.cmake: -D${var}=... is required")
  endif()
endforeach()
if("${CONFIG}" STREQUAL "")
  set(CONFIG Release)
endif()

# Runs one step; on failure prints its command and output and stops the script (non-zero exit).
function(step name)
  string(TIMESTAMP t0 "%s")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(TIMESTAMP t1 "%s")
  math(EXPR dt "${t1} - ${t0}")
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "package_consumer: step '${name}' failed (${rc}): ${cmd}\n--- stdout\n${out}\n--- stderr\n${err}")
  endif()
  message(STATUS "package_consumer: ${name}: ok (${dt} s)")
  set(step_output "${out}${err}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/build)
# Two ctest runs on one build tree would remove each other's prefix: take turns.
file(LOCK ${WORK_DIR}.lock GUARD PROCESS TIMEOUT 100)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# Settings shared by every consumer configure: same generator and compiler as the project, only the
# fresh prefix as a place to find lowpair (no user package registry).
set(configure_args -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${CONFIG}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)

# 1. install
step(install ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})

# 2. what was installed: the library, its headers and the package files, nothing else
set(cmakedir ${INSTALL_LIBDIR}/cmake/lowpair)
foreach(f ${INSTALL_INCLUDEDIR}/lowpair/kinematics.hpp ${cmakedir}/lowpairConfig.cmake
          ${cmakedir}/lowpairConfigVersion.cmake ${cmakedir}/lowpairTargets.cmake)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "package_consumer: ${f} was not installed")
  endif()
endforeach()
file(GLOB libs ${prefix}/${INSTALL_LIBDIR}/liblowpair.* ${prefix}/${INSTALL_LIBDIR}/lowpair.lib)
if(NOT libs)
  message(FATAL_ERROR "package_consumer: the library was not installed in ${INSTALL_LIBDIR}/")
endif()
file(GLOB_RECURSE installed RELATIVE ${prefix} ${prefix}/*)
foreach(f ${installed})
  if(NOT f MATCHES "^(${INSTALL_INCLUDEDIR}/lowpair/|${INSTALL_LIBDIR}/(cmake/lowpair/|(lib)?lowpair\\.)|(local/)?lib/python3[^/]*/(site|dist)-packages/lowpair/)")
    message(FATAL_ERROR "package_consumer: unexpected installed file ${f}")
  endif()
endforeach()
# the headers: exactly the supported API (the internals, check.hpp with its LP_ macros among them, are in
# lowpair/src and not installed;
# tests/consumer/CMakeLists.txt compiles each installed header alone)
# (version.hpp is generated into the build tree from cmake/version.hpp.in)
set(supported base_frame.hpp calibrate.hpp calibration.hpp convert.hpp cross_validation.hpp deflection.hpp dh_uncertainty.hpp error_model.hpp gravity.hpp
              identifiability.hpp ik.hpp ik_closed_form.hpp interrupt.hpp jacobian.hpp joint.hpp kinematics.hpp measure.hpp model.hpp plan.hpp
              registration.hpp robust_loss.hpp se3.hpp singularity.hpp
              tolerances.hpp types.hpp version.hpp)
file(GLOB headers RELATIVE ${prefix}/${INSTALL_INCLUDEDIR}/lowpair ${prefix}/${INSTALL_INCLUDEDIR}/lowpair/*)
list(SORT headers)
if(NOT headers STREQUAL supported)
  message(FATAL_ERROR "package_consumer: installed headers '${headers}', the supported API is '${supported}'")
endif()
file(STRINGS ${prefix}/${cmakedir}/lowpairTargets.cmake exported REGEX "add_library\\(")
if(NOT exported MATCHES "add_library\\(lowpair::lowpair " OR exported MATCHES "lowpair_core")
  message(FATAL_ERROR "package_consumer: the package should export exactly lowpair::lowpair, it has: ${exported}")
endif()

# 3. configure, build and run the consumer
step(configure ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${consumer_build} ${configure_args})
file(STRINGS ${consumer_build}/CMakeCache.txt found_dir REGEX "^lowpair_DIR:")
if(NOT found_dir STREQUAL "lowpair_DIR:PATH=${prefix}/${cmakedir}")
  message(FATAL_ERROR "package_consumer: lowpair was found outside the test prefix: ${found_dir}")
endif()
step(build ${CMAKE_COMMAND} --build ${consumer_build} --config ${CONFIG})
set(exe ${consumer_build}/consumer${CMAKE_EXECUTABLE_SUFFIX})
if(NOT EXISTS ${exe})
  set(exe ${consumer_build}/${CONFIG}/consumer${CMAKE_EXECUTABLE_SUFFIX})  # multi-config generators
endif()
step(run ${exe})
message(STATUS "${step_output}")

# 3b. the Python module, when the build made one: imported from the prefix alone (docs/python.md)
file(GLOB python_package LIST_DIRECTORIES true ${prefix}/lib/python3*/*-packages/lowpair
     ${prefix}/local/lib/python3*/*-packages/lowpair)
if(python_package AND EXISTS /usr/bin/python3)
  get_filename_component(python_site ${python_package} DIRECTORY)
  step(python_import ${CMAKE_COMMAND} -E env PYTHONPATH=${python_site} PYTHONNOUSERSITE=1 /usr/bin/python3 -c
       "import lowpair, numpy; assert lowpair.__file__.startswith('${python_site}'), lowpair.__file__; print('lowpair', lowpair.__file__)")
  message(STATUS "${step_output}")
endif()

# 4. the version file (SameMinorVersion): 0.3 satisfies neither 0.2 nor 0.4 (0.x minor releases break
#    the API) nor 1.0. These configures must fail, and fail for that reason.
foreach(v 0.2 0.4 1.0)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build-${v} ${configure_args}
                          -DREQUIRE_VERSION=${v}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "package_consumer: find_package(lowpair ${v} REQUIRED) was satisfied by the 0.3 package\n${out}${err}")
  endif()
  string(REGEX REPLACE "[ \t\r\n]+" " " flat "${out}${err}")  # CMake wraps its messages
  if(NOT flat MATCHES "compatible with requested version \"${v}\"")
    message(FATAL_ERROR "package_consumer: find_package(lowpair ${v}) failed, but not on the version:\n${out}${err}")
  endif()
  message(STATUS "package_consumer: find_package(lowpair ${v}) refused: ok")
endforeach()
