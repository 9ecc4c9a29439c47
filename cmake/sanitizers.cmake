# tricell_enable_sanitizers(target): AddressSanitizer + UndefinedBehaviorSanitizer when
# TRICELL_SANITIZE is ON, attached per target.
function(tricell_enable_sanitizers target)
    if(TRICELL_SANITIZE AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
        target_compile_options(${target} PRIVATE
            -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
        target_link_options(${target} PRIVATE -fsanitize=address,undefined)
    endif()
endfunction()
