# ecat_embed_files(<target> <base_dir> <files...>)
# Compiles the given files into <target> as byte arrays, named by their path
# relative to <base_dir> ("profiles/cia301.xml"). The .cpp is generated in the
# build tree at build time, so the files in the source tree stay the single
# source; esi/xml_embedded.hpp declares the lookup.
function(ecat_embed_files target base_dir)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}_embedded_files.cpp)
  string(JOIN "|" joined ${ARGN})
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DBASE=${base_dir} -DFILES=${joined}
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFilesScript.cmake
    DEPENDS ${ARGN} ${PROJECT_SOURCE_DIR}/cmake/EmbedFilesScript.cmake
    COMMENT "Embedding ${target} data files"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()
