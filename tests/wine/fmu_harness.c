/* A minimal FMI 2.0 co-simulation importer for Windows: loads the FMU's DLL the way a Windows
 * tool does (LoadLibraryW + GetProcAddress) and checks that it computes. Cross-compiled with
 * mingw-w64 and run under Wine by tests/python/test_win64.py, which prepares its inputs.
 *
 * usage: fmu_harness DLL GUID RESOURCE_URI RESOURCE_DIR PARAMETER_FILE FY_A2 CASES NAME=VR...
 *   DLL             path of Pacejka87Tire.dll
 *   GUID            the model description's guid
 *   RESOURCE_URI    file:///C:/... URI of the resources folder (fmuResourceLocation)
 *   RESOURCE_DIR    the same folder as a Windows path, as the FMU should log it
 *   PARAMETER_FILE  bare name of a parameter file in that folder, for `parameterFile`
 *   FY_A2           the Fy a2 coefficient that file sets
 *   CASES           text file, one case a line: Fz alpha kappa gamma Fx Fy Mz (SI units)
 *   NAME=VR         value references of Fz alpha kappa gamma Fx Fy Mz Fy_a2 parameterFile
 *
 * Prints one line per check, `ok NAME` or `FAIL NAME: detail`, other lines indented, and
 * exits with 1 if any check failed, 2 if the DLL could not be used at all.
 */
#include <windows.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2FunctionTypes.h" /* fmi-sys crate's copy of the FMI 2.0 standard headers */
#include "harness.h"          /* the log, the checks, the arguments */

/* Every function of FMI 2.0 for co-simulation (common functions and the CS ones). */
#define FMI2_CS_FUNCTIONS(X)                                                                      \
    X(GetTypesPlatform) X(GetVersion) X(SetDebugLogging) X(Instantiate) X(FreeInstance)           \
    X(SetupExperiment) X(EnterInitializationMode) X(ExitInitializationMode) X(Terminate)          \
    X(Reset) X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) X(SetReal) X(SetInteger)         \
    X(SetBoolean) X(SetString) X(GetFMUstate) X(SetFMUstate) X(FreeFMUstate)                     \
    X(SerializedFMUstateSize) X(SerializeFMUstate) X(DeSerializeFMUstate)                         \
    X(GetDirectionalDerivative) X(SetRealInputDerivatives) X(GetRealOutputDerivatives)           \
    X(DoStep) X(CancelStep) X(GetStatus) X(GetRealStatus) X(GetIntegerStatus)                     \
    X(GetBooleanStatus) X(GetStringStatus)

static struct {
#define FIELD(f) fmi2##f##TYPE *f;
    FMI2_CS_FUNCTIONS(FIELD)
} fmi;

enum { FZ, ALPHA, KAPPA, GAMMA, FX, FY, MZ, FY_A2, PARAMETER_FILE, N_VARS };
static const char *const VAR_NAMES[N_VARS] = {"Fz", "alpha", "kappa", "gamma", "Fx",
                                              "Fy", "Mz", "Fy_a2", "parameterFile"};
static fmi2ValueReference vr[N_VARS]; /* vr + FZ: the 4 inputs, vr + FX: the 3 outputs */
static const double H = 0.125;        /* communication step [s], exact in binary */

/* The FMU's messages, formatted, into the kept log (harness.h). */
static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    char text[1024];
    va_list args;
    va_start(args, message);
    vsnprintf(text, sizeof text, message ? message : "(NULL)", args);
    va_end(args);
    keep_message(instance, (int)status, category, text);
    (void)env;
}

static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};

/* ---- one instance and its communication point ---- */
typedef struct {
    fmi2Component c;
    double t;
} Tire;

static Tire instantiate(const char *name, const char *guid, const char *uri) {
    Tire tire = {fmi.Instantiate(name, fmi2CoSimulation, guid, uri, &callbacks, fmi2False,
                                 fmi2True),
                 0.0};
    return tire;
}

/* Setup, the parameter file (if any), enter and exit initialization: fmi2OK or the failure. */
static fmi2Status initialize(Tire *tire, const char *parameter_file) {
    fmi2Status s = fmi.SetupExperiment(tire->c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    if (s == fmi2OK && parameter_file)
        s = fmi.SetString(tire->c, &vr[PARAMETER_FILE], 1, &parameter_file);
    if (s == fmi2OK) s = fmi.EnterInitializationMode(tire->c);
    if (s == fmi2OK) s = fmi.ExitInitializationMode(tire->c);
    return s;
}

/* Sets the inputs, steps by H and reads the outputs: fmi2OK or the first failure. */
static fmi2Status step(Tire *tire, const double in[4], double out[3]) {
    fmi2Status s = fmi.SetReal(tire->c, vr + FZ, 4, in);
    if (s == fmi2OK) s = fmi.DoStep(tire->c, tire->t, H, fmi2True);
    if (s == fmi2OK) s = fmi.GetReal(tire->c, vr + FX, 3, out);
    tire->t += H;
    return s;
}

int wmain(int argc, wchar_t **argv) {
    setvbuf(stdout, NULL, _IONBF, 0); /* nothing lost if the DLL crashes the process */
    if (argc != 8 + N_VARS) {
        fprintf(stderr, "usage: fmu_harness DLL GUID RESOURCE_URI RESOURCE_DIR PARAMETER_FILE "
                        "FY_A2 CASES Fz=VR alpha=VR ... parameterFile=VR (see the source)\n");
        return 2;
    }
    const char *guid = utf8(argv[2]), *uri = utf8(argv[3]), *resource_dir = utf8(argv[4]);
    const char *parameter_file = utf8(argv[5]);
    const double fy_a2 = strtod(utf8(argv[6]), NULL);
    if (read_references(argv, 8, VAR_NAMES, N_VARS, vr)) return 2;

    HMODULE dll = LoadLibraryW(argv[1]);
    if (!dll) {
        printf("FAIL load_library: LoadLibraryW(%s) failed with Windows error %lu\n",
               utf8(argv[1]), GetLastError());
        return 2;
    }
    printf("ok load_library\n");
    char missing[1024] = "";
#define RESOLVE(f)                                                                                 \
    fmi.f = (fmi2##f##TYPE *)(void (*)(void))GetProcAddress(dll, "fmi2" #f);                       \
    if (!fmi.f) strcat(missing, " fmi2" #f);
    FMI2_CS_FUNCTIONS(RESOLVE)
    check(!missing[0], "resolve_functions", "not exported:%s", missing);
    if (missing[0]) return 2;

    const char *version = fmi.GetVersion(), *platform = fmi.GetTypesPlatform();
    check(version && !strcmp(version, "2.0"), "version", "fmi2GetVersion() = %s", version);
    check(platform && !strcmp(platform, fmi2TypesPlatform), "types_platform",
          "fmi2GetTypesPlatform() = %s", platform);

    /* Resources from a file:///C:/ URI with %20: the parameter file is found by its bare name. */
    int mark = n_logged;
    Tire params = instantiate("params", guid, uri);
    check(params.c && logged_since(mark, fmi2OK, "resources: ", resource_dir) == 1,
          "resource_uri", "%s: no instance logging its resources as %s", uri, resource_dir);
    double a2 = NAN; /* below, status fmi2Fatal stands for "no instance" */
    fmi2Status s = params.c ? initialize(&params, parameter_file) : fmi2Fatal;
    if (s == fmi2OK) s = fmi.GetReal(params.c, &vr[FY_A2], 1, &a2);
    check(s == fmi2OK && a2 == fy_a2, "parameter_file", "status %d, Fy_a2 = %.17g, expected %.17g",
          (int)s, a2, fy_a2);

    /* The reference values, one step per case. */
    Tire ref = instantiate("reference", guid, uri);
    s = ref.c ? initialize(&ref, NULL) : fmi2Fatal;
    check(s == fmi2OK, "instantiate_and_initialize", "status %d", (int)s);
    if (s != fmi2OK) return 1;
    FILE *cases = _wfopen(argv[7], L"r");
    double in[4], want[3], out[3];
    int rows = 0, bad = 0, bad_row = -1;
    char first_bad[512] = "";
    while (cases && fscanf(cases, "%lf %lf %lf %lf %lf %lf %lf", &in[0], &in[1], &in[2], &in[3],
                           &want[0], &want[1], &want[2]) == 7) {
        s = step(&ref, in, out);
        int row_ok = s == fmi2OK;
        row_ok &= matches_reference(out, want);
        if (!row_ok && bad++ == 0) {
            bad_row = rows;
            snprintf(first_bad, sizeof first_bad,
                     "status %d, Fx Fy Mz = %.17g %.17g %.17g, expected %.17g %.17g %.17g", (int)s,
                     out[0], out[1], out[2], want[0], want[1], want[2]);
        }
        rows++;
    }
    int read_all = cases && feof(cases);
    printf("  reference cases compared: %d\n", rows);
    check(rows > 0 && read_all && bad == 0, "reference_values",
          "%d of %d cases off (file read to its end: %d); first, case %d: %s", bad, rows, read_all,
          bad_row, first_bad);
    if (cases) fclose(cases);

    /* FMU state: get, step on with other inputs, set restores; serialized into a fresh instance. */
    const double A[4] = {5000.0, 0.08, -0.1, 0.02}, B[4] = {3000.0, -0.2, 0.3, -0.05};
    double saved[3], changed[3], restored[3];
    fmi2FMUstate state = NULL, state2 = NULL;
    s = step(&ref, A, saved);
    double saved_t = ref.t;
    if (s == fmi2OK) s = fmi.GetFMUstate(ref.c, &state);
    if (s == fmi2OK) s = step(&ref, B, changed);
    if (s == fmi2OK) s = fmi.SetFMUstate(ref.c, state);
    if (s == fmi2OK) s = fmi.GetReal(ref.c, vr + FX, 3, restored);
    check(s == fmi2OK && state && memcmp(saved, changed, sizeof saved) &&
              !memcmp(saved, restored, sizeof saved),
          "fmu_state_get_set",
          "status %d; Fy saved %.17g, after other inputs %.17g, restored %.17g",
          (int)s, saved[1], changed[1], restored[1]);
    ref.t = saved_t;

    size_t size = 0;
    char *bytes = NULL;
    Tire fresh = instantiate("fresh", guid, uri);
    s = fresh.c ? initialize(&fresh, NULL) : fmi2Fatal;
    if (s == fmi2OK) s = step(&fresh, B, changed);
    if (s == fmi2OK) s = fmi.SerializedFMUstateSize(ref.c, state, &size);
    if (s == fmi2OK && size > 0 && (bytes = malloc(size)))
        s = fmi.SerializeFMUstate(ref.c, state, bytes, size);
    if (s == fmi2OK && bytes) s = fmi.DeSerializeFMUstate(fresh.c, bytes, size, &state2);
    if (s == fmi2OK) s = fmi.SetFMUstate(fresh.c, state2);
    if (s == fmi2OK) s = fmi.GetReal(fresh.c, vr + FX, 3, restored);
    check(s == fmi2OK && bytes && !memcmp(saved, restored, sizeof saved), "fmu_state_serialize",
          "status %d, %zu bytes; Fy saved %.17g, in the fresh instance %.17g", (int)s, size,
          saved[1], restored[1]);
    free(bytes);
    fmi2Status s1 = fmi.FreeFMUstate(ref.c, &state), s2 = fmi.FreeFMUstate(fresh.c, &state2);
    check(s1 == fmi2OK && s2 == fmi2OK && !state && !state2, "fmu_state_free",
          "statuses %d %d, slots %p %p", (int)s1, (int)s2, state, state2);

    /* Hostile calls: errors, never crashes. */
    double x = 0.0;
    fmi2Status st = fmi2OK;
    fmi2FMUstate none = NULL;
    const fmi2Status null_calls[] = {
        fmi.SetupExperiment(NULL, fmi2False, 0.0, 0.0, fmi2False, 0.0),
        fmi.EnterInitializationMode(NULL), fmi.GetReal(NULL, vr, 1, &x),
        fmi.SetReal(NULL, vr, 1, &x), fmi.DoStep(NULL, 0.0, H, fmi2True),
        fmi.GetFMUstate(NULL, &none), fmi.SerializedFMUstateSize(NULL, NULL, &size),
        fmi.GetStatus(NULL, fmi2DoStepStatus, &st), fmi.Terminate(NULL), fmi.Reset(NULL)};
    int n_null = sizeof null_calls / sizeof null_calls[0], null_ok = 0;
    for (int i = 0; i < n_null; i++) null_ok += null_calls[i] == fmi2Error;
    fmi.FreeInstance(NULL); /* a no-op */
    check(null_ok == n_null, "null_instance", "%d of %d calls returned fmi2Error", null_ok, n_null);

    mark = n_logged;
    Tire early = instantiate("early", guid, uri);
    s = early.c ? fmi.DoStep(early.c, 0.0, H, fmi2True) : fmi2Fatal;
    check(s == fmi2Error && logged_since(mark, fmi2Error, "fmi2DoStep", "Illegal call sequence"),
          "step_before_initialization", "status %d, or no message", (int)s);
    if (early.c) fmi.FreeInstance(early.c);

    mark = n_logged;
    double alpha_before = NAN, alpha_after = NAN, nan = NAN;
    fmi.GetReal(ref.c, &vr[ALPHA], 1, &alpha_before);
    s = fmi.SetReal(ref.c, &vr[ALPHA], 1, &nan);
    fmi.GetReal(ref.c, &vr[ALPHA], 1, &alpha_after);
    check(s == fmi2Error && logged_since(mark, fmi2Error, "alpha", "NaN") == 1 &&
              alpha_after == alpha_before,
          "nan_input", "status %d, %d error messages naming alpha and NaN, alpha %.17g -> %.17g",
          (int)s, logged_since(mark, fmi2Error, "alpha", "NaN"), alpha_before, alpha_after);

    mark = n_logged;
    Tire wrong = instantiate("wrong_guid", "{00000000-0000-0000-0000-000000000000}", uri);
    check(!wrong.c && logged_since(mark, fmi2Error, "does not match", ""), "wrong_guid",
          "instance %p, or no message", wrong.c);
    if (wrong.c) fmi.FreeInstance(wrong.c);

    /* The end of a simulation. */
    s1 = fmi.Terminate(ref.c), s2 = fmi.Terminate(fresh.c);
    fmi2Status s3 = fmi.Terminate(params.c);
    check(s1 == fmi2OK && s2 == fmi2OK && s3 == fmi2OK, "terminate", "statuses %d %d %d",
          (int)s1, (int)s2, (int)s3);
    fmi.FreeInstance(ref.c);
    fmi.FreeInstance(fresh.c);
    fmi.FreeInstance(params.c);
    check(1, "free_instance", ""); /* getting here without a crash is the check */
    check(FreeLibrary(dll), "free_library", "Windows error %lu", GetLastError());
    printf("  %d check(s) failed\n", failures);
    return failures ? 1 : 0;
}
