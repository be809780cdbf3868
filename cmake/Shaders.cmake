# Compiles GLSL to SPIR-V at build time and embeds it as a C++ header (glslangValidator --vn).
# shaders/foo_bar.comp -> <build>/shaders/foo_bar_comp.h defining `const uint32_t foo_bar_comp[]`.
# Included headers (shaders/shared/*.h) are tracked through glslang's depfile.
function(penumbra_add_shaders target)
  set(outputs)
  foreach(src IN LISTS ARGN)
    get_filename_component(name ${src} NAME)
    string(REPLACE "." "_" var ${name})
    set(out ${CMAKE_BINARY_DIR}/shaders/${var}.h)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${GLSLANG_VALIDATOR} --target-env vulkan1.2 -g0 -I${CMAKE_SOURCE_DIR}/shaders
              --vn ${var} --depfile ${out}.d -o ${out} ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPFILE ${out}.d
      COMMENT "glslang ${src}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${target} DEPENDS ${outputs})
endfunction()
