/*
 * fmi_check: drives a hydrofmu library through its FMI 2.0 or FMI 3.0 functions, the way an
 * importer does, and writes what it reads back. One source for both platforms: compiled with
 * gcc against the Linux library (dlopen) and with x86_64-w64-mingw32-gcc against the Windows
 * DLL (LoadLibraryW); only the shim below differs.
 *
 *   fmi_check CONFIG OUTPUT
 *
 * CONFIG (UTF-8, one item a line): the standard (2 or 3), the library's path, the resource
 * location (FMI 2.0: a file: URI; FMI 3.0: a directory path), the GUID or instantiation
 * token, the velocity value references, the value references to read back, the parameter
 * assignments "vr=value ..." (Float64; "i:vr=value" an Int32 one; the line may be empty). Paths go through the file, not argv, so
 * non-ASCII folders reach the library intact on Windows too.
 *
 * Run: instantiate, set the parameters, initialize, 1000 steps of h = 0.01 s with the
 * velocity of DOF i equal to 0.3 sin(pi t + i), reading the outputs after each step. The
 * state after step 500 is taken, serialized, freed, deserialized and set again; steps
 * 501..1000 are run a second time and must repeat the first run bit for bit.
 *
 * OUTPUT: one line per step, "t out..." in %.17g; then "state <hex>" (the state serialized
 * after step 500) and "restored <n> steps identical". Exit status 0 only when every call
 * succeeded and the round trip held.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdarg.h>
#include <stdbool.h>
#include <math.h>

/* ---- platform shim: loading a library and finding a symbol ---- */
#ifdef _WIN32
#include <windows.h>
typedef HMODULE library_t;
static library_t library_open(const char *utf8_path) {
    wchar_t wide[4096];
    if (!MultiByteToWideChar(CP_UTF8, 0, utf8_path, -1, wide, 4096)) return NULL;
    return LoadLibraryW(wide);
}
static void *library_symbol(library_t lib, const char *name) {
    return (void *)GetProcAddress(lib, name);
}
static const char *library_error(void) {
    static char text[64];
    snprintf(text, sizeof text, "Windows error %lu", (unsigned long)GetLastError());
    return text;
}
#else
#include <dlfcn.h>
typedef void *library_t;
static library_t library_open(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *library_symbol(library_t lib, const char *name) { return dlsym(lib, name); }
static const char *library_error(void) { return dlerror(); }
#endif

#define STEPS 1000
#define STEP_SIZE 0.01
#define SAVE_AFTER 500
#define MAX_VR 256

static library_t library;

static void *symbol(const char *name) {
    void *f = library_symbol(library, name);
    if (!f) {
        fprintf(stderr, "fmi_check: %s not exported\n", name);
        exit(2);
    }
    return f;
}

static void fail(const char *call, int status) {
    fprintf(stderr, "fmi_check: %s returned status %d\n", call, status);
    exit(1);
}

#define CHECK(call, expr)                                                                   \
    do {                                                                                    \
        int status_ = (expr);                                                               \
        if (status_ != 0) fail(call, status_);                                              \
    } while (0)

/* ---- the configuration ---- */
static char lines[7][8192];
static unsigned velocity_vr[MAX_VR], output_vr[MAX_VR], parameter_vr[MAX_VR];
static double parameter_value[MAX_VR];
static unsigned integer_vr[MAX_VR];
static int integer_value[MAX_VR];
static size_t n_velocity, n_output, n_parameter, n_integer;

static void read_config(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "fmi_check: cannot open %s\n", path);
        exit(2);
    }
    for (int i = 0; i < 7; i++) {
        if (!fgets(lines[i], sizeof lines[i], f)) {
            if (i == 6) { lines[i][0] = 0; break; }
            fprintf(stderr, "fmi_check: %s: line %d missing\n", path, i + 1);
            exit(2);
        }
        lines[i][strcspn(lines[i], "\r\n")] = 0;
    }
    fclose(f);
    char *p = lines[4];
    int used;
    while (n_velocity < MAX_VR && sscanf(p, "%u%n", &velocity_vr[n_velocity], &used) == 1) {
        n_velocity++; p += used;
    }
    p = lines[5];
    while (n_output < MAX_VR && sscanf(p, "%u%n", &output_vr[n_output], &used) == 1) {
        n_output++; p += used;
    }
    p = lines[6];
    while (n_parameter < MAX_VR && n_integer < MAX_VR) {
        if (sscanf(p, " i:%u=%d%n", &integer_vr[n_integer], &integer_value[n_integer], &used) == 2)
            n_integer++;
        else if (sscanf(p, " %u=%lf%n", &parameter_vr[n_parameter], &parameter_value[n_parameter],
                        &used) == 2)
            n_parameter++;
        else
            break;
        p += used;
    }
    if (n_velocity == 0 || n_output == 0) {
        fprintf(stderr, "fmi_check: %s: no velocity or output value references\n", path);
        exit(2);
    }
}

static void velocities(double t, double *v) {
    for (size_t i = 0; i < n_velocity; i++) v[i] = 0.3 * sin(3.141592653589793 * t + (double)i);
}

/* ---- one interface: the calls both standards share, behind function pointers ---- */
typedef struct {
    void *instance;
    int (*set_real)(void *, const unsigned *, size_t, const double *);
    int (*get_real)(void *, const unsigned *, size_t, double *);
    int (*step)(void *, double t, double h);
    /* Takes the state, serializes it into a malloc'd buffer, frees the state. */
    int (*save)(void *, unsigned char **bytes, size_t *size);
    /* Deserializes the bytes and sets the state. */
    int (*restore)(void *, const unsigned char *bytes, size_t size);
    int (*terminate)(void *);
    void (*free_instance)(void *);
} Fmu;

/* ---- FMI 2.0 ---- */
typedef void (*fmi2Logger)(void *, const char *, int, const char *, const char *, ...);
typedef struct {
    fmi2Logger logger;
    void *(*allocate)(size_t, size_t);
    void (*free)(void *);
    void (*step_finished)(void *, int);
    void *environment;
} fmi2Callbacks;

static void logger2(void *env, const char *name, int status, const char *category,
                 const char *message, ...) {
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s %d %s] ", name ? name : "", status, category ? category : "");
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static int (*fmi2SetReal)(void *, const unsigned *, size_t, const double *);
static int (*fmi2GetReal)(void *, const unsigned *, size_t, double *);
static int (*fmi2DoStep)(void *, double, double, int);
static int (*fmi2GetFMUstate)(void *, void **);
static int (*fmi2SetFMUstate)(void *, void *);
static int (*fmi2FreeFMUstate)(void *, void **);
static int (*fmi2SerializedFMUstateSize)(void *, void *, size_t *);
static int (*fmi2SerializeFMUstate)(void *, void *, unsigned char *, size_t);
static int (*fmi2DeSerializeFMUstate)(void *, const unsigned char *, size_t, void **);

static int step2(void *c, double t, double h) { return fmi2DoStep(c, t, h, 0); }
static int save2(void *c, unsigned char **bytes, size_t *size) {
    void *state = NULL;
    CHECK("fmi2GetFMUstate", fmi2GetFMUstate(c, &state));
    CHECK("fmi2SerializedFMUstateSize", fmi2SerializedFMUstateSize(c, state, size));
    *bytes = malloc(*size);
    CHECK("fmi2SerializeFMUstate", fmi2SerializeFMUstate(c, state, *bytes, *size));
    return fmi2FreeFMUstate(c, &state);
}
static int restore2(void *c, const unsigned char *bytes, size_t size) {
    void *state = NULL;
    CHECK("fmi2DeSerializeFMUstate", fmi2DeSerializeFMUstate(c, bytes, size, &state));
    CHECK("fmi2SetFMUstate", fmi2SetFMUstate(c, state));
    return fmi2FreeFMUstate(c, &state);
}

static Fmu open2(void) {
    void *(*instantiate)(const char *, int, const char *, const char *, const fmi2Callbacks *,
                         int, int) = symbol("fmi2Instantiate");
    int (*setup)(void *, int, double, double, int, double) = symbol("fmi2SetupExperiment");
    int (*enter)(void *) = symbol("fmi2EnterInitializationMode");
    int (*exit_)(void *) = symbol("fmi2ExitInitializationMode");
    fmi2SetReal = symbol("fmi2SetReal");
    fmi2GetReal = symbol("fmi2GetReal");
    fmi2DoStep = symbol("fmi2DoStep");
    fmi2GetFMUstate = symbol("fmi2GetFMUstate");
    fmi2SetFMUstate = symbol("fmi2SetFMUstate");
    fmi2FreeFMUstate = symbol("fmi2FreeFMUstate");
    fmi2SerializedFMUstateSize = symbol("fmi2SerializedFMUstateSize");
    fmi2SerializeFMUstate = symbol("fmi2SerializeFMUstate");
    fmi2DeSerializeFMUstate = symbol("fmi2DeSerializeFMUstate");
    static const fmi2Callbacks callbacks = {logger2, calloc, free, NULL, NULL};
    void *c = instantiate("check", 1 /* fmi2CoSimulation */, lines[3], lines[2], &callbacks, 0, 0);
    if (!c) fail("fmi2Instantiate", -1);
    int (*set_integer)(void *, const unsigned *, size_t, const int *) = symbol("fmi2SetInteger");
    if (n_integer) CHECK("fmi2SetInteger (parameters)", set_integer(c, integer_vr, n_integer, integer_value));
    if (n_parameter) CHECK("fmi2SetReal (parameters)", fmi2SetReal(c, parameter_vr, n_parameter, parameter_value));
    CHECK("fmi2SetupExperiment", setup(c, 0, 0.0, 0.0, 0, 0.0));
    CHECK("fmi2EnterInitializationMode", enter(c));
    CHECK("fmi2ExitInitializationMode", exit_(c));
    Fmu fmu = {c, fmi2SetReal, fmi2GetReal, step2, save2, restore2, symbol("fmi2Terminate"),
               symbol("fmi2FreeInstance")};
    return fmu;
}

/* ---- FMI 3.0 ---- */
typedef void (*fmi3Logger)(void *, int, const char *, const char *);
static void logger3(void *env, int status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "[%d %s] %s\n", status, category ? category : "", message ? message : "");
}

static int (*fmi3SetFloat64)(void *, const unsigned *, size_t, const double *, size_t);
static int (*fmi3GetFloat64)(void *, const unsigned *, size_t, double *, size_t);
static int (*fmi3DoStep)(void *, double, double, bool, bool *, bool *, bool *, double *);
static int (*fmi3GetFMUState)(void *, void **);
static int (*fmi3SetFMUState)(void *, void *);
static int (*fmi3FreeFMUState)(void *, void **);
static int (*fmi3SerializedFMUStateSize)(void *, void *, size_t *);
static int (*fmi3SerializeFMUState)(void *, void *, unsigned char *, size_t);
static int (*fmi3DeserializeFMUState)(void *, const unsigned char *, size_t, void **);

static int set3(void *c, const unsigned *vr, size_t n, const double *v) {
    return fmi3SetFloat64(c, vr, n, v, n);
}
static int get3(void *c, const unsigned *vr, size_t n, double *v) {
    return fmi3GetFloat64(c, vr, n, v, n);
}
static int step3(void *c, double t, double h) {
    bool event = false, terminate = false, early = false;
    double last = 0.0;
    return fmi3DoStep(c, t, h, false, &event, &terminate, &early, &last);
}
static int save3(void *c, unsigned char **bytes, size_t *size) {
    void *state = NULL;
    CHECK("fmi3GetFMUState", fmi3GetFMUState(c, &state));
    CHECK("fmi3SerializedFMUStateSize", fmi3SerializedFMUStateSize(c, state, size));
    *bytes = malloc(*size);
    CHECK("fmi3SerializeFMUState", fmi3SerializeFMUState(c, state, *bytes, *size));
    return fmi3FreeFMUState(c, &state);
}
static int restore3(void *c, const unsigned char *bytes, size_t size) {
    void *state = NULL;
    CHECK("fmi3DeserializeFMUState", fmi3DeserializeFMUState(c, bytes, size, &state));
    CHECK("fmi3SetFMUState", fmi3SetFMUState(c, state));
    return fmi3FreeFMUState(c, &state);
}

static Fmu open3(void) {
    void *(*instantiate)(const char *, const char *, const char *, bool, bool, bool, bool,
                         const unsigned *, size_t, void *, fmi3Logger, void *) =
        symbol("fmi3InstantiateCoSimulation");
    int (*enter)(void *, bool, double, double, bool, double) = symbol("fmi3EnterInitializationMode");
    int (*exit_)(void *) = symbol("fmi3ExitInitializationMode");
    fmi3SetFloat64 = symbol("fmi3SetFloat64");
    fmi3GetFloat64 = symbol("fmi3GetFloat64");
    fmi3DoStep = symbol("fmi3DoStep");
    fmi3GetFMUState = symbol("fmi3GetFMUState");
    fmi3SetFMUState = symbol("fmi3SetFMUState");
    fmi3FreeFMUState = symbol("fmi3FreeFMUState");
    fmi3SerializedFMUStateSize = symbol("fmi3SerializedFMUStateSize");
    fmi3SerializeFMUState = symbol("fmi3SerializeFMUState");
    fmi3DeserializeFMUState = symbol("fmi3DeserializeFMUState");
    void *c = instantiate("check", lines[3], lines[2], false, false, false, false, NULL, 0, NULL,
                          logger3, NULL);
    if (!c) fail("fmi3InstantiateCoSimulation", -1);
    int (*set_int32)(void *, const unsigned *, size_t, const int32_t *, size_t) = symbol("fmi3SetInt32");
    if (n_integer) CHECK("fmi3SetInt32 (parameters)", set_int32(c, integer_vr, n_integer, (const int32_t *)integer_value, n_integer));
    if (n_parameter) CHECK("fmi3SetFloat64 (parameters)", set3(c, parameter_vr, n_parameter, parameter_value));
    CHECK("fmi3EnterInitializationMode", enter(c, false, 0.0, 0.0, false, 0.0));
    CHECK("fmi3ExitInitializationMode", exit_(c));
    Fmu fmu = {c, set3, get3, step3, save3, restore3, symbol("fmi3Terminate"),
               symbol("fmi3FreeInstance")};
    return fmu;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: fmi_check CONFIG OUTPUT\n");
        return 2;
    }
    read_config(argv[1]);
    library = library_open(lines[1]);
    if (!library) {
        fprintf(stderr, "fmi_check: cannot load %s: %s\n", lines[1], library_error());
        return 2;
    }
    Fmu fmu = strcmp(lines[0], "3") == 0 ? open3() : open2();
    FILE *out = fopen(argv[2], "wb");
    if (!out) {
        fprintf(stderr, "fmi_check: cannot write %s\n", argv[2]);
        return 2;
    }
    static double first[STEPS][MAX_VR];
    double v[MAX_VR];
    unsigned char *state = NULL;
    size_t state_size = 0;
    for (int k = 0; k < STEPS; k++) {
        double t = k * STEP_SIZE;
        if (k == SAVE_AFTER) CHECK("saving the state", fmu.save(fmu.instance, &state, &state_size));
        velocities(t, v);
        CHECK("set velocities", fmu.set_real(fmu.instance, velocity_vr, n_velocity, v));
        CHECK("do step", fmu.step(fmu.instance, t, STEP_SIZE));
        CHECK("get outputs", fmu.get_real(fmu.instance, output_vr, n_output, first[k]));
        fprintf(out, "%.17g", t + STEP_SIZE);
        for (size_t i = 0; i < n_output; i++) fprintf(out, " %.17g", first[k][i]);
        fputc('\n', out);
    }
    fputs("state ", out);
    for (size_t i = 0; i < state_size; i++) fprintf(out, "%02x", state[i]);
    fputc('\n', out);
    /* The round trip: back to step 500 from the serialized bytes, the same steps again. */
    CHECK("restoring the state", fmu.restore(fmu.instance, state, state_size));
    double again[MAX_VR];
    for (int k = SAVE_AFTER; k < STEPS; k++) {
        double t = k * STEP_SIZE;
        velocities(t, v);
        CHECK("set velocities", fmu.set_real(fmu.instance, velocity_vr, n_velocity, v));
        CHECK("do step", fmu.step(fmu.instance, t, STEP_SIZE));
        CHECK("get outputs", fmu.get_real(fmu.instance, output_vr, n_output, again));
        if (memcmp(again, first[k], n_output * sizeof(double)) != 0) {
            fprintf(stderr, "fmi_check: step %d after the restored state differs\n", k + 1);
            return 1;
        }
    }
    fprintf(out, "restored %d steps identical\n", STEPS - SAVE_AFTER);
    CHECK("terminate", fmu.terminate(fmu.instance));
    fmu.free_instance(fmu.instance);
    free(state);
    fclose(out);
    return 0;
}
