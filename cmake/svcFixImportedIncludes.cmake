# SPDX-License-Identifier: BSD-2-Clause
# Debian's OpenImageIO package lists /usr/include/opencv4 among its include
# directories even when OpenCV is not installed, which CMake rejects. Drop include
# directories of imported targets that do not exist.
function(svc_drop_missing_include_dirs target)
  if(NOT TARGET ${target})
    return()
  endif()
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    return()
  endif()
  set(kept "")
  foreach(dir IN LISTS dirs)
    if(EXISTS "${dir}" OR dir MATCHES "^\\$<")
      list(APPEND kept "${dir}")
    endif()
  endforeach()
  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${kept}")
endfunction()
svc_drop_missing_include_dirs(OpenImageIO::OpenImageIO)
svc_drop_missing_include_dirs(OpenImageIO::OpenImageIO_Util)
