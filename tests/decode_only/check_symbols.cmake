# ctest decode_only_symbols (label unit): capz::decode holds no encoder code (issue #39 item 4).
#   cmake -DNM=nm -DAR=ar -DDECODE_LIB=libcapz_decode.a -DENCODE_LIB=libcapz.a -P check_symbols.cmake
# Three rules, each a list of what breaks it:
#  1. no member of libcapz_decode.a is named *_encode.cpp.o, or like a member of libcapz.a (an
#     encoder file put in CAPZ_DECODE_SOURCES, cmake/sources.cmake);
#  2. no function libcapz.a defines (nm T: the encode files' entry points, whatever their names)
#     is also defined in libcapz_decode.a;
#  3. no function libcapz_decode.a defines (T, t, W or w, demangled) is named like an encoder's:
#     the payload writers and searches of the coder stages (kEncoderPatterns below, drawn from
#     the encode files), unless it is a file writer's (kWriterPatterns: writing a C3D, TRC or PCD
#     file is the decoder's last step, not the encoder's).
cmake_minimum_required(VERSION 3.16)
foreach(_v NM AR DECODE_LIB ENCODE_LIB)
  if(NOT ${_v})
    message(FATAL_ERROR "check_symbols.cmake needs -D${_v}=...")
  endif()
endforeach()

set(kEncoderPatterns
  "capz::([a-z0-9_]+::)*encode_[a-z0-9_]+\\("  # encode_positions, encode_mask, encode_meta, ...
  "capz::([a-z0-9_]+::|\\(anonymous namespace\\)::)*(choose|pick|plan|fit|infer)_[a-z0-9_]+\\("
  "capz::([a-z0-9_]+::)*find_(hold|interpolation|scaled)\\("
  "capz::([a-z0-9_]+::)*(IntEncoder|RangeEncoder|BitWriter|Encoder|ResidueWriter)::"
  "capz::([a-z0-9_]+::)*[A-Za-z0-9]+ResidueEncoder::"
  "capz::([a-z0-9_]+::)*lzma2_encode"
  "capz::([a-z0-9_]+::)*compress[a-z0-9_]*\\("
  "capz::([a-z0-9_]+::)*(write_file_header|append_chunk|write_model|write_repr_header)\\("
  "capz::([a-z0-9_]+::)*(write_value_table|write_hold|write_interp|write_runs)\\("
  "capz::([a-z0-9_]+::)*(candidate_representations|repeated_frames|hold_kept|interp_kept)\\("
  "capz::([a-z0-9_]+::)*(kept_samples|lattice_table|scaled_fits|quantise_(channel|window))\\("
  "capz::([a-z0-9_]+::)*(token_cost_bits|reference_energy|analog_hints|TokenTally::)"
  "capz::([a-z0-9_]+::)*(residuals_on_grid|is_colour_field|has_unit_candidate)\\("
  "capz::([a-z0-9_]+::)*(lpc_encode|lcps_encode|lcps_select|lpc_fit)\\("
  "capz::([a-z0-9_]+::)*(diff_bytes|pack)\\(")
set(kWriterPatterns
  "capz::c3d::(encode_c3d_file|encode_c3d_frames|encode_c3d_rotations|plan_c3d_file)\\("
  "capz::c3d::\\(anonymous namespace\\)::choose_layout\\("
  "capz::c3d::encode_parameter_section\\("  # the C3D writer's parameter section
  "capz::encode_c3d_parameters\\("          # the same bytes, for the promise check of META
  "capz::lzf_compress\\(")                  # PCD binary_compressed bodies

set(_fail "")

# Rule 1.
execute_process(COMMAND ${AR} t ${DECODE_LIB} OUTPUT_VARIABLE _dec_objs RESULT_VARIABLE _r1)
execute_process(COMMAND ${AR} t ${ENCODE_LIB} OUTPUT_VARIABLE _enc_objs RESULT_VARIABLE _r2)
if(_r1 OR _r2)
  message(FATAL_ERROR "${AR} t failed on ${DECODE_LIB} or ${ENCODE_LIB}")
endif()
string(REPLACE "\n" ";" _dec_objs "${_dec_objs}")
string(REPLACE "\n" ";" _enc_objs "${_enc_objs}")
foreach(_o IN LISTS _dec_objs)
  if(_o MATCHES "_encode\\.cpp\\.o$" OR (_o AND _o IN_LIST _enc_objs))
    string(APPEND _fail "  object ${_o}: an encoder file in capz::decode\n")
  endif()
endforeach()

# nm -C --defined-only -A: "LIB:OBJECT:ADDRESS TYPE NAME", one symbol a line (llvm-nm, which a
# clang build uses, puts a space before ADDRESS).
function(defined_symbols lib types out)
  execute_process(COMMAND ${NM} -C --defined-only -A ${lib} OUTPUT_VARIABLE _nm
                  RESULT_VARIABLE _r ERROR_QUIET)
  if(_r)
    message(FATAL_ERROR "${NM} failed on ${lib}")
  endif()
  string(REPLACE ";" "," _nm "${_nm}")  # demangled names may hold ';' (none expected)
  string(REPLACE "\n" ";" _nm "${_nm}")
  set(_res "")
  foreach(_line IN LISTS _nm)
    if(_line MATCHES "^[^:]*:([^:]+): ?[0-9a-f]+ ([${types}]) (.*)$")
      list(APPEND _res "${CMAKE_MATCH_1}|${CMAKE_MATCH_3}")
    endif()
  endforeach()
  set(${out} "${_res}" PARENT_SCOPE)
endfunction()

defined_symbols(${DECODE_LIB} "TtWw" _dec_syms)
defined_symbols(${ENCODE_LIB} "T" _enc_syms)

# Rule 2.
set(_dec_strong "")
foreach(_s IN LISTS _dec_syms)
  string(REGEX REPLACE "^[^|]*\\|" "" _name "${_s}")
  list(APPEND _dec_strong "${_name}")
endforeach()
foreach(_s IN LISTS _enc_syms)
  string(REGEX REPLACE "^([^|]*)\\|(.*)$" "\\1;\\2" _pair "${_s}")
  list(GET _pair 0 _obj)
  list(GET _pair 1 _name)
  if(NOT _name MATCHES "^(std::|__gnu_cxx::|typeinfo|vtable|guard variable)" AND
     _name IN_LIST _dec_strong)
    string(APPEND _fail "  ${_name}: defined by ${_obj} of capz::capz and in capz::decode\n")
  endif()
endforeach()

# Rule 3.
set(_checked 0)
foreach(_s IN LISTS _dec_syms)
  string(REGEX REPLACE "^([^|]*)\\|(.*)$" "\\1;\\2" _pair "${_s}")
  list(GET _pair 0 _obj)
  list(GET _pair 1 _name)
  math(EXPR _checked "${_checked} + 1")
  foreach(_p IN LISTS kEncoderPatterns)
    if(_name MATCHES "${_p}")
      set(_writer FALSE)
      foreach(_w IN LISTS kWriterPatterns)
        if(_name MATCHES "${_w}")
          set(_writer TRUE)
        endif()
      endforeach()
      if(NOT _writer)
        string(APPEND _fail "  ${_obj}: ${_name}\n")
      endif()
      break()
    endif()
  endforeach()
endforeach()

if(_checked LESS 100)
  message(FATAL_ERROR "only ${_checked} symbols read from ${DECODE_LIB}: is ${NM} working?")
endif()
if(_fail)
  message(FATAL_ERROR "encoder code in capz::decode (${DECODE_LIB}):\n${_fail}")
endif()
list(LENGTH _dec_objs _n_objs)
message(STATUS "capz::decode: ${_n_objs} objects, ${_checked} functions, no encoder code")
