# ctest stability.double.build: a second, double-precision build (RTMINI_DOUBLE=ON, -O1) of only the
# programs the stability suite runs (sketchtrace, bake) and the core unit tests (TARGETS), so that
# the suite and the BVH oracles run in float and in double from one CI build. Benchmarks and the
# optional image/HDF5/Embree libraries are off (the suite writes PPM and needs none of them);
# ccache is used when the parent build uses it.
# cmake -DSOURCE_DIR=... -DBUILD_DIR=... -DGENERATOR=... -DBUILD_TYPE=... -DKOKKOS_DIR=...
#       -DCXX=... -DTARGETS=sketchtrace,bake,... [-DLAUNCHER=ccache] [-DHOST_ARCH=...]
#       -P build_double.cmake
foreach(var SOURCE_DIR BUILD_DIR GENERATOR BUILD_TYPE KOKKOS_DIR CXX TARGETS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "build_double.cmake: -D${var}= is required")
  endif()
endforeach()
string(REPLACE "," ";" TARGETS "${TARGETS}")
set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER} -DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER})
endif()
set(arch)
if(DEFINED HOST_ARCH)
  set(arch "-DRTMINI_HOST_ARCH=${HOST_ARCH}")
endif()
# A Release copy at -O1: its tests run about as fast (measured on the 2-core VM: the double
# unit tests 46.3 s against 44.6 s at -O3, ao_disk 19.0 s against 17.4 s) and it compiles in
# about 0.6x the time (one unity unit: 47 s of CPU against 74 s), the largest single term of CI.
# The arithmetic is the same (no fast-math; contraction is off in both).
set(opt)
if(BUILD_TYPE STREQUAL "Release")
  set(opt "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG")
endif()
string(TIMESTAMP t0 "%s")
execute_process(
  COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${BUILD_DIR} -G ${GENERATOR}
          -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_CXX_COMPILER=${CXX} -DKokkos_DIR=${KOKKOS_DIR}
          -DRTMINI_DOUBLE=ON -DRTMINI_ENABLE_TESTS=ON -DRTMINI_ENABLE_BENCHMARKS=OFF
          -DRTMINI_ENABLE_PNG=OFF -DRTMINI_ENABLE_EXR=OFF -DRTMINI_ENABLE_HDF5=OFF
          -DRTMINI_ENABLE_EMBREE_PEER=OFF ${launcher} ${arch} ${opt}
          # Unity batches: the Kokkos headers parsed once per 16 files instead of once per file
          # (measured on 2 cores, cold: bake alone took 205 s of CPU file by file; bake,
          # sketchtrace and the core unit tests together 299 s in batches). A helper that two
          # files both define at namespace scope then clashes: name it apart or share it.
          -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "double build: configure failed (${rc})\n${out}\n${err}")
endif()
include(ProcessorCount)
ProcessorCount(jobs)
if(jobs LESS 1)
  set(jobs 2)
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${TARGETS} -j ${jobs}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "double build: build failed (${rc})\n${out}\n${err}")
endif()
string(TIMESTAMP t1 "%s")
math(EXPR secs "${t1} - ${t0}")
message(STATUS "double build of ${TARGETS} in ${BUILD_DIR}: ${secs} s")
