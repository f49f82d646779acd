/// @brief The sanitizers' default options and suppressions, linked into every executable of a
/// sanitizer build (CVC_SANITIZE), so that the tests, the `cvc` they start and a developer's own
/// runs all behave alike without environment variables. docs/robustness.md tells how each
/// suppression was shown to be the driver's or a library's and not ours.

extern "C" {

// Every report fails the process (no recovery, no leak-only warning), with a stack to read.
const char* __asan_default_options() { return "detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"; }
const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }

// Leaks of allocations made, and never freed, inside libraries we do not build. Each was seen in
// a program that only creates and destroys our Vulkan context, or only starts and finalizes MPI,
// and none of them goes away when our own code is left out:
// - lavapipe (libvulkan_lvp) and the LLVM that JIT-compiles its shaders keep per-process
//   caches (shader variants, LLVM's registries and options) until exit by design;
// - the Vulkan loader (libvulkan.so, dlopen'ed by vulkan.hpp's dynamic loader under that name)
//   keeps 48 bytes of its layer list: a one-frame stack, the loader has no frame pointers;
// - Open MPI's libraries and the components it dlopens (mca_*.so, under openmpi/) keep their
//   registries, strings and the PMIx/hwloc/libevent state they start; Open MPI documents these
//   and ships valgrind suppressions for them.
// A leak of our own Vulkan objects is not hidden by these: the validation layer (on in every
// GPU test) reports each object not destroyed before its device.
const char* __lsan_default_suppressions() {
    return "leak:libvulkan_lvp.so\n"
           "leak:libLLVM-15.so\n"
           "leak:libvulkan.so\n"
           "leak:libmpi.so\n"
           "leak:libopen-pal.so\n"
           "leak:libopen-rte.so\n"
           "leak:libpmix.so\n"
           "leak:libhwloc.so\n"
           "leak:libevent\n"
           "leak:/openmpi/\n"
           // Under mpirun a rank also leaks strings from glibc's vasprintf whose caller's frame
           // is lost (the library that called it has no frame pointers). None of our code calls
           // asprintf or vasprintf (a grep of the tree finds none); Open MPI and PMIx do.
           "leak:vasprintf\n";
}

// ThreadSanitizer sees the synchronisation of instrumented code only. TBB (under OpenVDB's
// volumeToMesh and leaf iteration), the validation layer, lavapipe and LLVM synchronise their
// threads in libraries we do not build, so TSan reports every hand-over there as a race: in
// their frames, or in TBB's and OpenVDB's header templates compiled into our code. These reports
// are suppressed; a race whose stacks are ours alone (our threads, std::thread and std::async,
// atomics and mutexes) is still reported.
const char* __tsan_default_suppressions() {
    return "race:libtbb.so\n"
           "race:libopenvdb.so\n"
           "race:tbb::\n"
           "race:openvdb::\n"
           "race:libVkLayer_khronos_validation.so\n"
           "race:libvulkan_lvp.so\n"
           "race:libLLVM-15.so\n"
           "called_from_lib:libtbb.so\n"
           "called_from_lib:libVkLayer_khronos_validation.so\n"
           "called_from_lib:libvulkan_lvp.so\n"
           // LLVM's JIT takes its own locks in an order TSan cannot follow through the driver.
           "deadlock:libLLVM-15.so\n"
           "deadlock:libvulkan_lvp.so\n"
           "deadlock:libVkLayer_khronos_validation.so\n";
}

// Libraries are never unloaded in a sanitizer build. LeakSanitizer reports at exit, and a
// library that the Vulkan loader or Open MPI has dlclose'd by then shows in a stack as
// "<unknown module>", which no suppression can name; kept loaded, every frame names its library.
// The executable's definition takes the place of libc's for every library that calls dlclose.
int dlclose(void* /*handle*/) { return 0; }

}  // extern "C"
