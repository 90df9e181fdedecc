# The no-heap proof for a firmware image: fails when the symbol table of FILE (an ELF or a
# static library) defines or references anything that allocates, throws, unwinds or carries
# RTTI. Run as a POST_BUILD step of every MCU image (so such a build fails) and as a ctest.
#
#   cmake -DNM=arm-none-eabi-nm -DFILE=<elf|archive> -P NoHeapCheck.cmake
#
# A referenced symbol counts as much as a defined one: an undefined reference in an object
# means the code would allocate if linked, and in a linked image an undefined reference that
# the linker left unresolved is still a call site.
cmake_minimum_required(VERSION 3.25)

if(NOT NM OR NOT FILE)
  message(FATAL_ERROR "usage: cmake -DNM=<nm> -DFILE=<elf|archive> -P NoHeapCheck.cmake")
endif()
if(NOT EXISTS "${FILE}")
  message(FATAL_ERROR "no-heap: ${FILE} does not exist")
endif()

# Each rule: a regular expression over the raw (mangled) name, and why it is forbidden.
set(rules
  "^(malloc|free|calloc|realloc|reallocf|memalign|aligned_alloc|posix_memalign|valloc|pvalloc)$|heap allocation"
  "^_(malloc|free|calloc|realloc|memalign)_r$|heap allocation (newlib reentrant)"
  "^_?sbrk(_r)?$|heap growth"
  "^_Zn[wa]|operator new"
  "^_Zd[la]|operator delete"
  "^__cxa_(allocate|free)_exception$|exception allocation"
  "^__cxa_(throw|rethrow|begin_catch|end_catch)$|exception handling"
  "^__gxx_personality_v0$|exception handling"
  "^_Unwind_|stack unwinding"
  "^_ZTI|RTTI typeinfo"
  "^_ZTS|RTTI typeinfo name"
  "^(__cxa_atexit|__aeabi_atexit|atexit)$|static-destructor registration (must not be needed, newlib may allocate for it)"
)

execute_process(COMMAND "${NM}" "${FILE}"
                RESULT_VARIABLE nm_result OUTPUT_VARIABLE nm_output ERROR_VARIABLE nm_error)
if(NOT nm_result EQUAL 0)
  message(FATAL_ERROR "no-heap: ${NM} ${FILE} failed (${nm_result}): ${nm_error}")
endif()

string(REPLACE "\n" ";" lines "${nm_output}")
set(checked 0)
set(found "")
foreach(line IN LISTS lines)
  # "<address> <type> <name>" or "         U <name>"; archive member headers are skipped.
  if(NOT line MATCHES "^[0-9a-fA-F ]* ([A-Za-z?-]) ([^ ]+)$")
    continue()
  endif()
  set(type "${CMAKE_MATCH_1}")
  set(name "${CMAKE_MATCH_2}")
  math(EXPR checked "${checked} + 1")
  foreach(rule IN LISTS rules)
    string(FIND "${rule}" "|" bar REVERSE)
    string(SUBSTRING "${rule}" 0 ${bar} pattern)
    math(EXPR after "${bar} + 1")
    string(SUBSTRING "${rule}" ${after} -1 why)
    if(name MATCHES "${pattern}")
      if(type STREQUAL "U" OR type STREQUAL "w" OR type STREQUAL "v")
        set(how "referenced")
      else()
        set(how "defined")
      endif()
      list(APPEND found "  ${how} ${name} (${why})")
      break()
    endif()
  endforeach()
endforeach()

get_filename_component(shown "${FILE}" NAME)
if(checked EQUAL 0)
  message(FATAL_ERROR "no-heap: ${shown}: nm listed no symbols, nothing was checked")
endif()
if(found)
  list(REMOVE_DUPLICATES found)
  list(LENGTH found count)
  string(REPLACE ";" "\n" report "${found}")
  message("no-heap: ${shown}: FAIL, ${count} forbidden symbol(s):\n${report}")
  message(FATAL_ERROR "no-heap: ${shown} allocates, throws, unwinds or uses RTTI")
endif()
message("no-heap: ${shown}: ok, none of ${checked} symbols allocates, throws, unwinds or uses RTTI")
