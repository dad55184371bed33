# SPDX-License-Identifier: BSD-2-Clause
# pkg-config files svc-decoder.pc and svc.pc. Relocatable: the prefix is derived from
# the directory the .pc file is found in. `pkg-config --libs` gives a complete link line
# without --static: the static libraries' dependencies are listed in Libs/Requires.
set(_pc_dir "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
if(IS_ABSOLUTE "${_pc_dir}")
  set(SVC_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  # One ".." per component of lib/pkgconfig (lib/x86_64-linux-gnu/pkgconfig has three).
  string(REGEX REPLACE "[^/]+" ".." _up "${_pc_dir}")
  set(SVC_PC_PREFIX "\${pcfiledir}/${_up}")
endif()
# A C program links the static C++ library through the C compiler: name its runtime.
set(SVC_PC_DECODER_DEPS "Libs: -L\${libdir} -lsvc_decoder -pthread -lstdc++ -lm")
set(SVC_PC_FULL_DEPS "Requires: svc-decoder OpenImageIO OpenEXR\nLibs: -L\${libdir} -lsvc -pthread")
foreach(_pc svc-decoder svc)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${_pc}.pc.in ${PROJECT_BINARY_DIR}/${_pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${_pc}.pc DESTINATION ${_pc_dir})
endforeach()
