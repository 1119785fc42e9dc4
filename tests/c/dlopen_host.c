/*
 * A C host that links no libm (tests/test_fmu_libm.py): loads an FMU's
 * binary with every symbol bound at once (RTLD_NOW) and prints the FMI
 * version it reports.
 *
 *   dlopen_host LIBRARY fmi2GetVersion|fmi3GetVersion
 *
 * Exit status 1 with dlerror() when the library cannot be loaded.
 */
#include <dlfcn.h>
#include <stdio.h>

int main(int argc, char **argv) {
    void *lib;
    const char *(*version)(void);
    if (argc != 3) return 2;
    lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "%s\n", dlerror());
        return 1;
    }
    *(void **)&version = dlsym(lib, argv[2]);
    if (!version) {
        fprintf(stderr, "%s\n", dlerror());
        return 1;
    }
    printf("%s\n", version());
    return 0;
}
