// A shared library without a registration function.
extern "C" int trephine_not_a_plugin() { return 0; }
