# Runs ddsimp_bench_memory on a small surface; fails unless it exits 0 and prints its JSON report.
# No bound on the memory is asserted here: on a tiny surface page granularity dominates.
# Called by ctest with -DBENCH=... -DSURFACE=... -DSTRATEGY=edge|vertex
foreach(var BENCH SURFACE STRATEGY)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "check_memory_bench.cmake: -D${var}=... is required")
    endif()
endforeach()

execute_process(
    COMMAND "${BENCH}" "${SURFACE}" --strategy "${STRATEGY}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
message("${stdout}${stderr}")
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "ddsimp_bench_memory exited with '${rc}', expected 0")
endif()

foreach(key triangles_in triangles_out bytes_per_triangle heap_bytes_per_triangle peak_rss_valid)
    string(JSON ${key} ERROR_VARIABLE err GET "${stdout}" ${key})
    if(err)
        message(FATAL_ERROR "ddsimp_bench_memory printed no '${key}': ${err}")
    endif()
endforeach()
if(NOT triangles_out GREATER 0 OR triangles_out GREATER triangles_in)
    message(FATAL_ERROR "implausible: triangles_in=${triangles_in} triangles_out=${triangles_out}")
endif()
if(NOT peak_rss_valid)
    message(FATAL_ERROR "the peak RSS mark could not be reset (/proc/self/clear_refs)")
endif()
