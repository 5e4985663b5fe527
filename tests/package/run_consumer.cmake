# ctest driver: cmake --install the build into WORK_DIR/prefix, then configure, build and run the
# consumer project against it twice: with the consumer's default flags (Release) and with
# -O3 -march=x86-64-v3 (FMA available), and require byte-identical results. LINK_FLAGS carries the
# sanitizer runtime when the installed library was built with -fsanitize. Fails on the first step
# that fails.
file(REMOVE_RECURSE ${WORK_DIR})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)

# The exported target must carry the flags: -march=x86-64-v3 alone would fuse a*b+c.
file(READ ${WORK_DIR}/prefix/lib/cmake/tessera/tesseraTargets.cmake targets)
if(NOT targets MATCHES "-ffp-contract=off")
  message(FATAL_ERROR "tessera::tessera does not export -ffp-contract=off in INTERFACE_COMPILE_OPTIONS")
endif()

foreach(variant default v3)
  set(flags "")
  if(variant STREQUAL "v3")
    set(flags "-O3 -march=x86-64-v3")
  endif()
  step(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build-${variant} -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
       -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
       "-DCMAKE_CXX_FLAGS=${flags}" "-DCMAKE_EXE_LINKER_FLAGS=${LINK_FLAGS}")
  step(${CMAKE_COMMAND} --build ${WORK_DIR}/build-${variant})
endforeach()

step(${WORK_DIR}/build-default/consumer ${WORK_DIR}/default.bin)
# x86-64-v3 needs AVX2, FMA, BMI2 (every machine this project runs on has them); elsewhere the
# v3 binary cannot run, and the test says so instead of passing.
file(READ /proc/cpuinfo cpuinfo)
foreach(feature avx2 fma bmi2)
  if(NOT cpuinfo MATCHES " ${feature}[ \n]")
    message(FATAL_ERROR "this CPU lacks ${feature}: the x86-64-v3 consumer cannot run here")
  endif()
endforeach()
step(${WORK_DIR}/build-v3/consumer ${WORK_DIR}/v3.bin)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK_DIR}/default.bin ${WORK_DIR}/v3.bin RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "the -O3 -march=x86-64-v3 consumer computes different bits from the default build "
                      "(${WORK_DIR}/default.bin vs v3.bin)")
endif()
message(STATUS "consumer: default and -O3 -march=x86-64-v3 builds agree bit for bit")
