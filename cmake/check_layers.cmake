# The layers' rule (ARCHITECTURE.md, "Layers"): a folder includes only its own headers and
# those of the layers below it,
#   sim < campaign < stats < checks < design, bench < app
# so that data flow one way and each library links only what lies below it. Run as a test
# (tests/CMakeLists.txt, check_layers): cmake -DSOURCE=<repository> -P cmake/check_layers.cmake
# fails naming every file that includes a higher layer's header, and the line.
if(NOT SOURCE)
  message(FATAL_ERROR "check_layers.cmake: give -DSOURCE=<repository root>")
endif()
set(jam_layers sim campaign stats checks design bench app)
set(jam_rank_sim 0)
set(jam_rank_campaign 1)
set(jam_rank_stats 2)
set(jam_rank_checks 3)
set(jam_rank_design 4)
set(jam_rank_bench 4)
set(jam_rank_app 5)
set(jam_broken "")
foreach(layer IN LISTS jam_layers)
  file(GLOB_RECURSE jam_files ${SOURCE}/${layer}/*.cpp ${SOURCE}/${layer}/*.hpp
       ${SOURCE}/${layer}/*.in)
  foreach(file IN LISTS jam_files)
    file(STRINGS ${file} jam_includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[a-z_]+/")
    foreach(line IN LISTS jam_includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"([a-z_]+)/.*" "\\1" included "${line}")
      if(DEFINED jam_rank_${included} AND jam_rank_${included} GREATER jam_rank_${layer})
        file(RELATIVE_PATH shown ${SOURCE} ${file})
        string(APPEND jam_broken "  ${shown}: ${line} (${layer} is below ${included})\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(jam_broken)
  message(FATAL_ERROR "a lower layer includes a higher one:\n${jam_broken}")
endif()
message(STATUS "layers: no folder includes a layer above it")
