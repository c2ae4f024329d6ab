// librfsitl (src/CMakeLists.txt) is the static libraries of src/ linked whole;
// a shared library needs one source file of its own, and this is it.
