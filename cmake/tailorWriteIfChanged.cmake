# tailor_write_if_changed(<file> <text>): writes the file only when its text changes, so that a
# generated source rewritten at build time does not make its users recompile.
function(tailor_write_if_changed file text)
  set(_old "")
  if(EXISTS ${file})
    file(READ ${file} _old)
  endif()
  if(NOT _old STREQUAL text)
    file(WRITE ${file} "${text}")
  endif()
endfunction()
