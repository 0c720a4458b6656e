# ecatslave_generate(<name> DEVICE <device.xml> [NAMESPACE <c++ namespace>])
#
# Runs ecat-esigen at build time on a device description and makes, in
# ${CMAKE_CURRENT_BINARY_DIR}/<name>/:
#   <name>.xml  the ESI (ETG.2000)          -> variable <name>_ESI
#   <name>.bin  the SII EEPROM image        -> variable <name>_SII
#   <name>.hpp  constexpr C++ tables        -> variable <name>_HEADER
# and an INTERFACE library <name> whose include path holds <name>.hpp: link it
# and `#include "<name>.hpp"`. The outputs are rebuilt when the device file or
# ecat-esigen changes. NAMESPACE defaults to <name> (with - replaced by _).
function(ecatslave_generate name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "DEVICE;NAMESPACE" "")
  if(NOT arg_DEVICE)
    message(FATAL_ERROR "ecatslave_generate(${name}): DEVICE <file> is required")
  endif()
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "ecatslave_generate(${name}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT arg_NAMESPACE)
    string(MAKE_C_IDENTIFIER "${name}" arg_NAMESPACE)
  endif()
  get_filename_component(device "${arg_DEVICE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/${name})
  set(esi ${dir}/${name}.xml)
  set(sii ${dir}/${name}.bin)
  set(header ${dir}/${name}.hpp)
  add_custom_command(
    OUTPUT ${esi} ${sii} ${header}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
    COMMAND ecatslave::ecat-esigen ${device} --esi ${esi} --sii ${sii} --cpp ${header}
            --cpp-namespace ${arg_NAMESPACE}
    DEPENDS ${device} ecatslave::ecat-esigen
    COMMENT "ecat-esigen: ESI, SII and C++ tables of ${arg_DEVICE}"
    VERBATIM)
  add_custom_target(${name}_generate DEPENDS ${esi} ${sii} ${header})
  add_library(${name} INTERFACE)
  target_include_directories(${name} INTERFACE ${dir})
  add_dependencies(${name} ${name}_generate)
  set(${name}_ESI ${esi} PARENT_SCOPE)
  set(${name}_SII ${sii} PARENT_SCOPE)
  set(${name}_HEADER ${header} PARENT_SCOPE)
endfunction()
