# ASan + UBSan for every target; UB is made fatal so ctest sees it. -O1 as the
# sanitizers' own documentation advises: at -O0 Eigen's expression templates
# run ~1000x slower than optimised and the simulator's 10 s runs would not fit
# CI's time; -O1 keeps the checks (and Debug's asserts) at a fraction of that.
add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1)
add_link_options(-fsanitize=address,undefined)
