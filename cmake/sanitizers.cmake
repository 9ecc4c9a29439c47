# tricell_enable_sanitizers(target): AddressSanitizer + UndefinedBehaviorSanitizer when
# TRICELL_SANITIZE is ON, attached per target. When the fuzzers are built as well
# (TRICELL_BUILD_FUZZERS), every tricell target also gets libFuzzer's coverage instrumentation
# (-fsanitize=fuzzer-no-link), so that the fuzzers see the edges of the library they call.
# TRICELL_SANITIZE_THREAD attaches ThreadSanitizer instead (scripts/test.sh builds only the
# threading tests that way: parallel_test, concurrency_stress_test, c_concurrency_stress_test,
# fork_test).
function(tricell_enable_sanitizers target)
    if(TRICELL_SANITIZE_THREAD AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
        target_compile_options(${target} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
        target_link_options(${target} PRIVATE -fsanitize=thread)
    endif()
    if(TRICELL_SANITIZE AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
        target_compile_options(${target} PRIVATE
            -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
        target_link_options(${target} PRIVATE -fsanitize=address,undefined)
        if(TRICELL_BUILD_FUZZERS)
            target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
        endif()
    endif()
endfunction()

# tricell_fuzzing_available(result): whether this compiler links a libFuzzer program
# (clang with compiler-rt; Debian: clang-14 libclang-rt-14-dev). Sets result in the caller.
function(tricell_fuzzing_available result)
    include(CheckCXXSourceCompiles)
    set(CMAKE_REQUIRED_FLAGS "-fsanitize=fuzzer,address,undefined")
    set(CMAKE_REQUIRED_LINK_OPTIONS "-fsanitize=fuzzer,address,undefined")
    check_cxx_source_compiles([[
        #include <cstddef>
        #include <cstdint>
        extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t) { return 0; }
    ]] TRICELL_HAVE_LIBFUZZER)
    set(${result} ${TRICELL_HAVE_LIBFUZZER} PARENT_SCOPE)
endfunction()
