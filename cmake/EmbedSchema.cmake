# jam_embed_schema(TARGET SCHEMA TEMPLATE HEADER): reference/schema/SCHEMA, one of the files
# that define a format once, embedded in TARGET as the text of a generated header (TEMPLATE,
# whose @JAM_SCHEMA_TOML@ it fills, written to generated/HEADER in the current binary
# directory), so that jam checks a file by the very rules jamio reads from the same TOML, with
# no file to find at run time. A change to the schema reconfigures.
function(jam_embed_schema target schema template header)
  set(path ${PROJECT_SOURCE_DIR}/reference/schema/${schema})
  file(READ ${path} JAM_SCHEMA_TOML)
  configure_file(${template} ${CMAKE_CURRENT_BINARY_DIR}/generated/${header} @ONLY)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${path})
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR}/generated)
endfunction()
