# Installs the build tree into a scratch prefix, then configures, builds and
# runs samples/ against the installed sdcbConfig.cmake, and samples/core_only
# with COMPONENTS core while Draco, OpenMesh and nlohmann_json are hidden.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/samples -B ${WORK_DIR}/build
                -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring samples/ against the installed package failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building samples/ failed")
endif()
execute_process(COMMAND ${WORK_DIR}/build/mesh_summary ${MESH} RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "genus 0")
  message(FATAL_ERROR "samples/mesh_summary did not run correctly")
endif()
execute_process(COMMAND ${WORK_DIR}/build/fit_surface ${MESH} 0.5 RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "control points")
  message(FATAL_ERROR "samples/fit_surface did not run correctly")
endif()

execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/samples/core_only
                -B ${WORK_DIR}/build_core_only
                -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                -DCMAKE_DISABLE_FIND_PACKAGE_draco=TRUE
                -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=TRUE
                -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=TRUE
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "find_package(sdcb COMPONENTS core) needed more than core's dependencies")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build_core_only
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building samples/core_only failed")
endif()
execute_process(COMMAND ${WORK_DIR}/build_core_only/thread_limits RESULT_VARIABLE rc
                OUTPUT_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "thread limits respected")
  message(FATAL_ERROR "samples/core_only/thread_limits: the library changed the program's TBB limits")
endif()
