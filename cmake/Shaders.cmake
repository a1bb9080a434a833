# GLSL -> SPIR-V at build time with glslangValidator, embedded as a C++ array in a generated
# header (`--vn`), so no shader file is looked up at run time. A compile error fails the build
# and glslang names the file and line. Dependencies on #included files come from --depfile.
function(gt_add_shaders target)
  cmake_parse_arguments(ARG "" "" "SOURCES;INCLUDE_DIRS" ${ARGN})
  set(out_dir ${CMAKE_BINARY_DIR}/generated/shaders)
  file(MAKE_DIRECTORY ${out_dir})
  set(headers)
  set(inc_flags)
  foreach(dir ${ARG_INCLUDE_DIRS})
    list(APPEND inc_flags -I${dir})
  endforeach()
  foreach(src ${ARG_SOURCES})
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(name ${src} NAME)
    string(REPLACE "." "_" ident ${name})
    set(header ${out_dir}/${ident}.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.2 ${inc_flags} --quiet
              --depfile ${header}.d --vn gt_spv_${ident} -o ${header} ${abs}
      DEPENDS ${abs}
      DEPFILE ${header}.d
      COMMENT "glslang ${name}"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${target}_spv DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_spv)
  target_include_directories(${target} INTERFACE ${out_dir})
endfunction()
