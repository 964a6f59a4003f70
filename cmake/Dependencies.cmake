# Every dependency is a Debian 12 package; a missing one stops configuration and names the package
# to install (scripts/setup.sh installs them all).
macro(hdrc_require package debian_package)
  find_package(${package} ${ARGN} QUIET)
  if(NOT ${package}_FOUND)
    message(FATAL_ERROR "hdrconform needs ${package}: install the Debian package "
                        "'${debian_package}' (apt-get install ${debian_package}), "
                        "or run scripts/setup.sh")
  endif()
endmacro()

hdrc_require(OpenImageIO libopenimageio-dev CONFIG)
hdrc_require(OpenEXR libopenexr-dev CONFIG)
hdrc_require(Imath libimath-dev CONFIG)
hdrc_require(GTest libgtest-dev)
hdrc_require(nlohmann_json nlohmann-json3-dev CONFIG)
hdrc_require(CLI11 libcli11-dev CONFIG)
hdrc_require(Vulkan libvulkan-dev)
hdrc_require(glslang glslang-dev CONFIG)
hdrc_require(SPIRV-Tools spirv-tools CONFIG)  # test-only: spirv-val of rewritten modules
# Debian 12 installs its config file directly in /usr/share/cmake.
hdrc_require(OpenColorIO libopencolorio-dev CONFIG PATHS /usr/share/cmake)  # test-only oracle

# Debian 12 packaging bugs: OpenImageIO's exported target lists /usr/include/opencv4 (present only
# with libopencv-dev, which OIIO's headers do not need) and OpenColorIO's lists "/include". Drop
# include directories that do not exist rather than install OpenCV.
function(hdrc_drop_missing_include_dirs target)
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    return()
  endif()
  set(kept)
  foreach(d IN LISTS dirs)
    if(EXISTS "${d}" OR d MATCHES "^\\$<")
      list(APPEND kept "${d}")
    endif()
  endforeach()
  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${kept}")
endfunction()
hdrc_drop_missing_include_dirs(OpenImageIO::OpenImageIO)
hdrc_drop_missing_include_dirs(OpenImageIO::OpenImageIO_Util)
hdrc_drop_missing_include_dirs(OpenColorIO::OpenColorIO)
