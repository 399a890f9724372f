#pragma once
// TREPHINE_INTERFACE marks an interface of the framework that components of
// different plugins meet through (a link's target type): its type information
// is exported from the framework's library that defines its destructor (the
// key function), so every plugin's dynamic_cast compares the one object, not
// type names.
#define TREPHINE_INTERFACE __attribute__((visibility("default")))
