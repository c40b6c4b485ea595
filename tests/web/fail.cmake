# A test that fails with the reason it was given (a prerequisite is missing).
message(FATAL_ERROR "${WHY}")
