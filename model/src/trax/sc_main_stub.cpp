// libsystemc's own main() calls sc_main(). The rayunits executables and tests have their own
// main(), so this is never called, but libsystemc.so needs the symbol at link time: the top
// CMakeLists.txt links everything that uses rayunits_model with `-u sc_main`, which pulls in
// this object. (An executable with its own sc_main, e.g. a SystemC testbench, keeps its own:
// the archive member is then not needed.)
extern "C" int sc_main(int, char**) { return 1; }
