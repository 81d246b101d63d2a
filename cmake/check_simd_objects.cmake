# Test simd_kernel_objects: the friction kernel files compiled for AVX2 and
# AVX-512 (friction/batch_kernels_avx2.cpp, _avx512.cpp) must not define any
# weak symbol.  A weak symbol is an inline function (a destructor, a string
# constructor, a standard algorithm) that other files may also define, compiled
# with their own flags; the linker keeps one copy for every caller, and if it
# keeps the AVX one, code that runs on any CPU (the baseline path) would
# execute AVX instructions.  Everything those files define must therefore be
# local to them (anonymous namespace) except their exported kernel table.
# Also checks that the wider flags took effect (zmm registers in the AVX-512
# object, ymm in the AVX2 object).
#   cmake -DAR=ar -DNM=nm -DOBJDUMP=objdump -DARCHIVE=libslipstrip_friction.a -P check_simd_objects.cmake
foreach(var AR NM OBJDUMP ARCHIVE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_simd_objects: -D${var}=... is required")
  endif()
endforeach()

set(failures "")
foreach(member batch_kernels_avx2.cpp.o batch_kernels_avx512.cpp.o)
  # Extract the member into a scratch directory (ar x writes into the cwd).
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/check_simd_objects)
  file(MAKE_DIRECTORY ${dir})
  execute_process(COMMAND ${AR} x ${ARCHIVE} ${member} WORKING_DIRECTORY ${dir}
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS ${dir}/${member})
    message(FATAL_ERROR "check_simd_objects: ${member} is not in ${ARCHIVE}: ${err}")
  endif()
  execute_process(COMMAND ${NM} -C --defined-only ${dir}/${member} OUTPUT_VARIABLE symbols
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_simd_objects: ${NM} failed on ${member}")
  endif()
  string(REPLACE "\n" ";" lines "${symbols}")
  set(weak 0)
  foreach(line ${lines})
    # "<address> <type> <name>"; weak or unique types: W w V v u i.
    if(line MATCHES "^[0-9a-fA-F]* +([WwVvui]) +(.*)$")
      set(name "${CMAKE_MATCH_2}")
      # The exception-personality references are data, not code.
      if(NOT name MATCHES "^DW\\.ref\\.")
        string(APPEND failures "  ${member}: weak symbol ${name}\n")
        math(EXPR weak "${weak} + 1")
      endif()
    endif()
  endforeach()
  execute_process(COMMAND ${OBJDUMP} -d --no-show-raw-insn ${dir}/${member} OUTPUT_VARIABLE code
                  RESULT_VARIABLE rc)
  if(member MATCHES "avx512")
    set(register "%zmm")
  else()
    set(register "%ymm")
  endif()
  string(FIND "${code}" "${register}" at)
  if(at EQUAL -1)
    string(APPEND failures "  ${member}: no ${register} register used: were the wider flags applied?\n")
  endif()
  message(STATUS "${member}: ${weak} weak symbols; uses ${register}")
endforeach()

if(failures)
  message(FATAL_ERROR "check_simd_objects: code compiled for AVX2/AVX-512 may be shared with "
                      "baseline callers:\n${failures}Move such code into a file compiled with the "
                      "build's own flags (see friction/batch_kernels.hpp).")
endif()
