# Finds tessera's Debian 12 dependencies through their CMake config packages and works around
# Debian 12's packaging pitfalls (each explained where it is handled below).
find_package(glm CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(hwy CONFIG REQUIRED)     # Highway (libhwy-dev): portable SIMD with runtime dispatch, target hwy::hwy
find_package(embree 3 CONFIG REQUIRED)  # Intel Embree 3.13 (libembree-dev): shadow rays, target `embree`
if(TESSERA_WITH_OIIO)
find_package(OpenImageIO CONFIG REQUIRED)
# Debian's OpenImageIO target lists /usr/include/opencv4, which only exists with
# libopencv-core-dev installed; CMake refuses non-existent include paths at generate time.
foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(_dirs OpenImageIO::OpenImageIO ${_prop})
  if(_dirs)
    list(FILTER _dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${_prop} "${_dirs}")
  endif()
endforeach()
else()
  # libstb-dev ships stb_image compiled as libstb.so (no CMake package).
  find_library(TESSERA_STB_LIBRARY stb REQUIRED)
endif()
# `tessera serve`'s HTTP server: cpp-httplib (libcpp-httplib-dev) ships no CMake package, only a
# pkg-config file; its compiled half is libcpp-httplib.so.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
find_package(TinyGLTF CONFIG REQUIRED)   # target TinyGLTF::TinyGLTF (shared library on Debian)
find_package(nlohmann_json CONFIG REQUIRED)
if(TESSERA_BUILD_TESTS)
  find_package(doctest CONFIG REQUIRED)
endif()
if(TESSERA_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
