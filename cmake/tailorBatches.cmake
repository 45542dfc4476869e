# Batched compilation (docs/testing.md, "Build time"): a library's .cpp files are compiled in
# batches, one translation unit per batch, so that the Eigen and standard headers are parsed, and
# their shared templates instantiated, once per batch instead of once per file. Two files of a
# library must therefore not define the same name in their anonymous namespaces.
#
# CMake's own UNITY_BUILD is not used: its batch files include the sources by absolute path, so
# a compiler cache (ccache) cannot reuse a build from a checkout in another folder. Ours include
# them by paths relative to the batch file (written at build time by cmake/tailorWriteBatch.cmake).
#
#   tailor_batch_sources(<target> SOURCES <files...> [BATCH_SIZE <n>] [ALONE <files...>])
#
# ALONE: files compiled as their own translation units (the fixed-size autodiff ones, which are
# long; alone they compile in parallel with the batches instead of lengthening one).
# With TAILOR_UNITY_BUILD off, every file is compiled on its own.
include_guard(GLOBAL)

# Files per batch. Larger batches parse the headers and instantiate the shared templates fewer
# times (docs/testing.md, "Build time"); an edit recompiles its whole batch.
set(TAILOR_BATCH_SIZE 16 CACHE STRING "Source files per batch (TAILOR_UNITY_BUILD)")

set(_tailor_batch_writer ${CMAKE_CURRENT_LIST_DIR}/tailorWriteBatch.cmake)

function(tailor_batch_sources target)
  cmake_parse_arguments(ARG "" "BATCH_SIZE" "SOURCES;ALONE" ${ARGN})
  if(NOT ARG_BATCH_SIZE)
    set(ARG_BATCH_SIZE ${TAILOR_BATCH_SIZE})
  endif()
  if(NOT TAILOR_UNITY_BUILD)
    target_sources(${target} PRIVATE ${ARG_SOURCES})
    return()
  endif()
  set(_batched)
  set(_alone)
  foreach(_source ${ARG_SOURCES})
    get_filename_component(_source ${_source} ABSOLUTE)
    set(_is_alone OFF)
    foreach(_pattern ${ARG_ALONE})
      if(_source MATCHES "/${_pattern}$")
        set(_is_alone ON)
      endif()
    endforeach()
    if(_is_alone)
      list(APPEND _alone ${_source})
    else()
      list(APPEND _batched ${_source})
    endif()
  endforeach()
  list(SORT _batched)
  list(LENGTH _batched _count)
  set(_batch_dir ${CMAKE_CURRENT_BINARY_DIR}/${target}_batches)
  # ceil(count / size) batches of near-equal size (9 files: 5 + 4, not 8 + 1).
  math(EXPR _batches "(${_count} + ${ARG_BATCH_SIZE} - 1) / ${ARG_BATCH_SIZE}")
  set(_index 0)
  set(_start 0)
  while(_start LESS _count)
    math(EXPR _take "(${_count} - ${_start} + ${_batches} - ${_index} - 1) / (${_batches} - ${_index})")
    list(SUBLIST _batched ${_start} ${_take} _members)
    math(EXPR _start "${_start} + ${_take}")
    if(_take EQUAL 1)
      # A batch of one is the file itself.
      list(APPEND _alone ${_members})
      math(EXPR _index "${_index} + 1")
      continue()
    endif()
    set(_output ${_batch_dir}/batch_${_index}.cpp)
    string(REPLACE ";" "|" _encoded "${_members}")
    add_custom_command(OUTPUT ${_output}
      COMMAND ${CMAKE_COMMAND} -DOUTPUT=${_output} "-DSOURCES=${_encoded}" -P ${_tailor_batch_writer}
      DEPENDS ${_members} ${_tailor_batch_writer}
      COMMENT "Batch ${_index} of ${target}" VERBATIM)
    target_sources(${target} PRIVATE ${_output})
    math(EXPR _index "${_index} + 1")
  endwhile()
  # The batched files stay in the target's source list (IDEs, globbing) but are not compiled.
  if(_alone)
    list(REMOVE_ITEM _batched ${_alone})
  endif()
  target_sources(${target} PRIVATE ${_batched} ${_alone})
  if(_batched)
    set_source_files_properties(${_batched} TARGET_DIRECTORY ${target} PROPERTIES HEADER_FILE_ONLY ON)
  endif()
endfunction()
