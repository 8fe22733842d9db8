# Unity builds: a target's files compiled a few to a translation unit, so the torch precompiled
# header is loaded, and torch's inline code compiled, once per unity file rather than once per file
# (7 s and 5-10 s of every torch file's 12-24 s on 2 cores; docs/profiling.md, "Build time"). The
# torch targets use it, and the reports and unit tests, whose small files each parse the same
# headers. -DFSCIL_UNITY_BUILD=OFF compiles every file alone.
#
# Not CMake's UNITY_BUILD: it includes each file by its absolute path, so the unity files of a
# clone in another folder differ from this one's, and ccache (which rewrites paths on the command
# line only) compiles them all again in every CI clone. Ours include each file by its path from the
# top of the source tree, found through -I, which ccache does rewrite.
option(FSCIL_UNITY_BUILD "compile the files of the larger targets a few to a translation unit" ON)

# fscil_unity_build(TARGET [BY_FOLDER]): TARGET's C++ files in unity files of 8, in the order the
# target lists them; BY_FOLDER: one unity file per folder (a method folder is one translation unit,
# so touching a method's file recompiles that method). A file with its own compile definitions or
# SKIP_UNITY_BUILD_INCLUSION is compiled alone.
function(fscil_unity_build target)
  if(NOT FSCIL_UNITY_BUILD)
    return()
  endif()
  cmake_parse_arguments(arg "BY_FOLDER" "" "" ${ARGN})
  get_target_property(sources ${target} SOURCES)
  set(groups "")
  set(count 0)
  foreach(source IN LISTS sources)
    get_source_file_property(alone ${source} SKIP_UNITY_BUILD_INCLUSION)
    get_source_file_property(definitions ${source} COMPILE_DEFINITIONS)
    if(NOT source MATCHES "\\.cpp$" OR alone OR definitions)
      continue()
    endif()
    get_filename_component(path ${source} ABSOLUTE)
    file(RELATIVE_PATH from_top ${PROJECT_SOURCE_DIR} ${path})
    if(arg_BY_FOLDER)
      file(RELATIVE_PATH group ${CMAKE_CURRENT_SOURCE_DIR} ${path})
      get_filename_component(group "${group}" DIRECTORY)
      string(MAKE_C_IDENTIFIER "${group}" group)
      if(group STREQUAL "")
        set(group top)  # the target's own folder
      endif()
    else()
      math(EXPR group "${count} / 8")
      math(EXPR count "${count} + 1")
    endif()
    if(NOT group IN_LIST groups)
      list(APPEND groups ${group})
      set(content_${group} "")
    endif()
    string(APPEND content_${group} "#include \"${from_top}\"\n")
    set_source_files_properties(${source} PROPERTIES HEADER_FILE_ONLY ON)
  endforeach()
  foreach(group IN LISTS groups)
    set(unity_file ${CMAKE_CURRENT_BINARY_DIR}/unity/${target}_${group}.cpp)
    file(CONFIGURE OUTPUT ${unity_file} CONTENT "${content_${group}}")  # rewritten only when it changes
    target_sources(${target} PRIVATE ${unity_file})
  endforeach()
endfunction()
