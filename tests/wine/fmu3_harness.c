/* A minimal FMI 3.0 co-simulation importer for Windows: loads the FMU's DLL the way a Windows
 * tool does (LoadLibraryW + GetProcAddress) and checks that it computes. Cross-compiled with
 * mingw-w64 and run under Wine by tests/python/test_win64_fmi3.py, which prepares its inputs.
 * The FMI 2.0 counterpart is fmu_harness.c.
 *
 * usage: fmu3_harness DLL TOKEN RESOURCE_PATH PARAMETER_FILE FY_A2 CASES NAME=VR...
 *   DLL             path of Pacejka87Tire.dll
 *   TOKEN           the model description's instantiationToken
 *   RESOURCE_PATH   the resources folder as a Windows path ending in a backslash (resourcePath)
 *   PARAMETER_FILE  bare name of a parameter file in that folder, for `parameterFile`
 *   FY_A2           the Fy a2 coefficient that file sets
 *   CASES           text file, one case a line: Fz alpha kappa gamma Fx Fy Mz (SI units)
 *   NAME=VR         value references of Fz alpha kappa gamma Fx Fy Mz Fy_coefficients
 *                   parameterFile
 *
 * Prints one line per check, `ok NAME` or `FAIL NAME: detail`, other lines indented, and
 * exits with 1 if any check failed, 2 if the DLL could not be used at all.
 */
#include <windows.h>

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3FunctionTypes.h" /* fmi-sys crate's copy of the FMI 3.0 standard headers */
#include "harness.h"          /* the log, the checks, the arguments */

/* Every function of fmi3FunctionTypes.h (75): common, co-simulation, Model Exchange,
 * scheduled execution and clocks. */
#define FMI3_FUNCTIONS(X)                                                                         \
    X(GetVersion) X(SetDebugLogging) X(InstantiateModelExchange) X(InstantiateCoSimulation)       \
    X(InstantiateScheduledExecution) X(FreeInstance) X(EnterInitializationMode)                   \
    X(ExitInitializationMode) X(EnterEventMode) X(Terminate) X(Reset) X(GetFloat32)               \
    X(GetFloat64) X(GetInt8) X(GetUInt8) X(GetInt16) X(GetUInt16) X(GetInt32) X(GetUInt32)        \
    X(GetInt64) X(GetUInt64) X(GetBoolean) X(GetString) X(GetBinary) X(GetClock) X(SetFloat32)    \
    X(SetFloat64) X(SetInt8) X(SetUInt8) X(SetInt16) X(SetUInt16) X(SetInt32) X(SetUInt32)        \
    X(SetInt64) X(SetUInt64) X(SetBoolean) X(SetString) X(SetBinary) X(SetClock)                  \
    X(GetNumberOfVariableDependencies) X(GetVariableDependencies) X(GetFMUState)                  \
    X(SetFMUState) X(FreeFMUState) X(SerializedFMUStateSize) X(SerializeFMUState)                 \
    X(DeserializeFMUState) X(GetDirectionalDerivative) X(GetAdjointDerivative)                    \
    X(EnterConfigurationMode) X(ExitConfigurationMode) X(GetIntervalDecimal)                      \
    X(GetIntervalFraction) X(GetShiftDecimal) X(GetShiftFraction) X(SetIntervalDecimal)           \
    X(SetIntervalFraction) X(SetShiftDecimal) X(SetShiftFraction) X(EvaluateDiscreteStates)       \
    X(UpdateDiscreteStates) X(EnterContinuousTimeMode) X(CompletedIntegratorStep) X(SetTime)      \
    X(SetContinuousStates) X(GetContinuousStateDerivatives) X(GetEventIndicators)                 \
    X(GetContinuousStates) X(GetNominalsOfContinuousStates) X(GetNumberOfEventIndicators)         \
    X(GetNumberOfContinuousStates) X(EnterStepMode) X(GetOutputDerivatives) X(DoStep)             \
    X(ActivateModelPartition)

static struct {
#define FIELD(f) fmi3##f##TYPE *f;
    FMI3_FUNCTIONS(FIELD)
} fmi;

enum { FZ, ALPHA, KAPPA, GAMMA, FX, FY, MZ, FY_COEFFICIENTS, PARAMETER_FILE, N_VARS };
static const char *const VAR_NAMES[N_VARS] = {"Fz", "alpha", "kappa", "gamma", "Fx",
                                              "Fy", "Mz", "Fy_coefficients", "parameterFile"};
static fmi3ValueReference vr[N_VARS]; /* vr + FZ: the 4 inputs, vr + FX: the 3 outputs */
static const double H = 0.125;        /* communication step [s], exact in binary */

/* Fy_coefficients C a1..a13: the paper's table (the start values), and that with a3 changed. */
enum { N_COEFFICIENTS = 14, A2 = 2, A3 = 3 };
static const double FY_PAPER[N_COEFFICIENTS] = {1.3,  -22.1, 1011.0, 1078.0, 1.82,
                                                0.208, 0.0,  -0.354, 0.707,  0.028,
                                                0.0,  14.8, 0.022,  0.0};
static const double FY_A3 = 1347.5; /* 1.25 times the paper's 1078, exact in binary */

/* The FMU's messages into the kept log (harness.h); the instance environment is the
 * instance's name (FMI 3.0 passes no name to the logger). */
static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                   fmi3String message) {
    keep_message(env ? (const char *)env : NULL, (int)status, category, message);
}

/* ---- one instance and its communication point ---- */
typedef struct {
    fmi3Instance c;
    double t;
} Tire;

/* A co-simulation instance, logging on, no event mode, no early return; `name` is its
 * environment (a string literal: it outlives the instance). */
static Tire instantiate(const char *name, const char *token, const char *resources) {
    Tire tire = {fmi.InstantiateCoSimulation(name, token, resources, false, true, false, false,
                                             NULL, 0, (fmi3InstanceEnvironment)name, logger,
                                             NULL),
                 0.0};
    return tire;
}

/* The parameter file (if any), enter and exit initialization: fmi3OK or the failure. */
static fmi3Status initialize(Tire *tire, const char *parameter_file) {
    fmi3Status s = fmi3OK;
    if (parameter_file) s = fmi.SetString(tire->c, &vr[PARAMETER_FILE], 1, &parameter_file, 1);
    if (s == fmi3OK) s = fmi.EnterInitializationMode(tire->c, false, 0.0, 0.0, false, 0.0);
    if (s == fmi3OK) s = fmi.ExitInitializationMode(tire->c);
    return s;
}

/* Out-parameters of the last fmi3DoStep that were not those of a plain full step. */
static int odd_steps;

/* Sets the inputs, steps by H and reads the outputs: fmi3OK or the first failure. */
static fmi3Status step(Tire *tire, const double in[4], double out[3]) {
    bool event = true, terminate = true, early = true;
    double last = NAN;
    fmi3Status s = fmi.SetFloat64(tire->c, vr + FZ, 4, in, 4);
    if (s == fmi3OK)
        s = fmi.DoStep(tire->c, tire->t, H, false, &event, &terminate, &early, &last);
    if (s == fmi3OK) {
        odd_steps += event || terminate || early || last != tire->t + H;
        s = fmi.GetFloat64(tire->c, vr + FX, 3, out, 3);
    }
    tire->t += H;
    return s;
}

/* |a - b| within `rel` of the larger magnitude (both 0 agree). */
static int close_to(double a, double b, double rel) {
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b));
}

/* A reproducible number in [-1, 1) (a 64-bit LCG, upper bits). */
static double uniform(void) {
    static unsigned long long x = 0x9e3779b97f4a7c15ULL;
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(x >> 11) / 4503599627370496.0 - 1.0; /* 2^52: [0, 2) - 1 */
}

enum { MAX_CASES = 4096, DERIVATIVE_EVERY = 16 }; /* the cases kept; every 16th: derivatives */
static double case_inputs[MAX_CASES][4];

int wmain(int argc, wchar_t **argv) {
    setvbuf(stdout, NULL, _IONBF, 0); /* nothing lost if the DLL crashes the process */
    if (argc != 7 + N_VARS) {
        fprintf(stderr, "usage: fmu3_harness DLL TOKEN RESOURCE_PATH PARAMETER_FILE FY_A2 CASES "
                        "Fz=VR alpha=VR ... parameterFile=VR (see the source)\n");
        return 2;
    }
    const char *token = utf8(argv[2]), *resources = utf8(argv[3]);
    const char *parameter_file = utf8(argv[4]);
    const double fy_a2 = strtod(utf8(argv[5]), NULL);
    if (read_references(argv, 7, VAR_NAMES, N_VARS, vr)) return 2;

    HMODULE dll = LoadLibraryW(argv[1]);
    if (!dll) {
        printf("FAIL load_library: LoadLibraryW(%s) failed with Windows error %lu\n",
               utf8(argv[1]), GetLastError());
        return 2;
    }
    printf("ok load_library\n");
    char missing[2048] = "";
    int n_functions = 0;
#define RESOLVE(f)                                                                                 \
    fmi.f = (fmi3##f##TYPE *)(void (*)(void))GetProcAddress(dll, "fmi3" #f);                       \
    if (!fmi.f) strcat(missing, " fmi3" #f);                                                       \
    n_functions++;
    FMI3_FUNCTIONS(RESOLVE)
    printf("  functions resolved: %d\n", n_functions);
    check(!missing[0] && n_functions == 75, "resolve_functions", "of %d, not exported:%s",
          n_functions, missing);
    if (missing[0]) return 2;

    const char *version = fmi.GetVersion();
    check(version && !strcmp(version, "3.0"), "version", "fmi3GetVersion() = %s", version);

    /* Resources from a plain Windows path: the parameter file is found by its bare name. */
    char logged_resources[1024];
    snprintf(logged_resources, sizeof logged_resources, "resources: %s", resources);
    int mark = n_logged;
    Tire params = instantiate("params", token, resources);
    check(params.c && logged_since(mark, fmi3OK, logged_resources, "") == 1, "resource_path",
          "%s: no instance logging `%s`", resources, logged_resources);
    double fy[N_COEFFICIENTS] = {NAN}; /* below, status fmi3Fatal stands for "no instance" */
    fmi3Status s = params.c ? initialize(&params, parameter_file) : fmi3Fatal;
    if (s == fmi3OK)
        s = fmi.GetFloat64(params.c, &vr[FY_COEFFICIENTS], 1, fy, N_COEFFICIENTS);
    check(s == fmi3OK && fy[A2] == fy_a2, "parameter_file",
          "status %d, Fy_coefficients[%d] (a2) = %.17g, expected %.17g", (int)s, A2, fy[A2],
          fy_a2);

    /* The coefficient array, set before initialization and read back after it. */
    double coefficients[N_COEFFICIENTS], read_back[N_COEFFICIENTS] = {NAN};
    memcpy(coefficients, FY_PAPER, sizeof coefficients);
    coefficients[A3] = FY_A3;
    Tire coef = instantiate("coefficients", token, resources);
    s = coef.c ? fmi.SetFloat64(coef.c, &vr[FY_COEFFICIENTS], 1, coefficients, N_COEFFICIENTS)
               : fmi3Fatal;
    if (s == fmi3OK) s = initialize(&coef, NULL);
    if (s == fmi3OK)
        s = fmi.GetFloat64(coef.c, &vr[FY_COEFFICIENTS], 1, read_back, N_COEFFICIENTS);
    check(s == fmi3OK && !memcmp(coefficients, read_back, sizeof read_back), "coefficient_array",
          "status %d; Fy_coefficients[%d] (a3) = %.17g, expected %.17g", (int)s, A3,
          read_back[A3], FY_A3);

    /* The reference values, one step per case. */
    Tire ref = instantiate("reference", token, resources);
    s = ref.c ? initialize(&ref, NULL) : fmi3Fatal;
    check(s == fmi3OK, "instantiate_and_initialize", "status %d", (int)s);
    if (s != fmi3OK) return 1;
    FILE *cases = _wfopen(argv[6], L"r");
    double in[4], want[3], out[3];
    int rows = 0, bad = 0, bad_row = -1;
    char first_bad[512] = "";
    while (cases && fscanf(cases, "%lf %lf %lf %lf %lf %lf %lf", &in[0], &in[1], &in[2], &in[3],
                           &want[0], &want[1], &want[2]) == 7) {
        int odd_before = odd_steps;
        s = step(&ref, in, out);
        int row_ok = s == fmi3OK && odd_steps == odd_before;
        row_ok &= matches_reference(out, want);
        if (!row_ok && bad++ == 0) {
            bad_row = rows;
            snprintf(first_bad, sizeof first_bad,
                     "status %d, odd doStep out-parameters %d, Fx Fy Mz = %.17g %.17g %.17g, "
                     "expected %.17g %.17g %.17g",
                     (int)s, odd_steps - odd_before, out[0], out[1], out[2], want[0], want[1],
                     want[2]);
        }
        if (rows < MAX_CASES) memcpy(case_inputs[rows], in, sizeof in);
        rows++;
    }
    int read_all = cases && feof(cases);
    printf("  reference cases compared: %d\n", rows);
    check(rows > 0 && read_all && bad == 0, "reference_values",
          "%d of %d cases off (file read to its end: %d); first, case %d: %s", bad, rows, read_all,
          bad_row, first_bad);
    if (cases) fclose(cases);

    /* Derivatives at every 16th case: J by columns (directional) and by rows (adjoint). */
    int n_derivative = 0, n_nonzero = 0, bad_derivative = 0;
    char first_derivative[512] = "";
    for (int k = 0; k < rows && k < MAX_CASES; k += DERIVATIVE_EVERY) {
        double J[3][4], JT[3][4], seed[4], column[3], u[4], v[3], Ju[3], vJ[4];
        const char *what = "";
        s = step(&ref, case_inputs[k], out);
        for (int j = 0; j < 4 && s == fmi3OK; j++) {
            for (int i = 0; i < 4; i++) seed[i] = i == j;
            s = fmi.GetDirectionalDerivative(ref.c, vr + FX, 3, vr + FZ, 4, seed, 4, column, 3);
            for (int i = 0; i < 3; i++) J[i][j] = column[i];
        }
        for (int i = 0; i < 3 && s == fmi3OK; i++) {
            for (int j = 0; j < 3; j++) seed[j] = i == j;
            s = fmi.GetAdjointDerivative(ref.c, vr + FX, 3, vr + FZ, 4, seed, 3, JT[i], 4);
        }
        for (int j = 0; j < 4; j++) u[j] = uniform();
        for (int i = 0; i < 3; i++) v[i] = uniform();
        if (s == fmi3OK)
            s = fmi.GetDirectionalDerivative(ref.c, vr + FX, 3, vr + FZ, 4, u, 4, Ju, 3);
        if (s == fmi3OK) s = fmi.GetAdjointDerivative(ref.c, vr + FX, 3, vr + FZ, 4, v, 3, vJ, 4);
        int ok = s == fmi3OK, nonzero = 0;
        double vJu = 0.0, vJu2 = 0.0, scale = 0.0;
        for (int i = 0; i < 3 && ok; i++)
            for (int j = 0; j < 4; j++) {
                if (!close_to(J[i][j], JT[i][j], 1e-12)) what = "directional and adjoint J differ";
                ok &= close_to(J[i][j], JT[i][j], 1e-12);
                nonzero |= J[i][j] != 0.0;
                scale += fabs(v[i] * J[i][j] * u[j]);
            }
        for (int i = 0; i < 3; i++) vJu += v[i] * Ju[i];
        for (int j = 0; j < 4; j++) vJu2 += vJ[j] * u[j];
        if (ok && !(fabs(vJu - vJu2) <= 1e-12 * scale)) {
            what = "v.(J u) != (v^T J).u";
            ok = 0;
        }
        if (!ok && bad_derivative++ == 0)
            snprintf(first_derivative, sizeof first_derivative,
                     "case %d: status %d, %s; dFy/dalpha %.17g (directional) %.17g (adjoint), "
                     "v.(J u) %.17g, (v^T J).u %.17g",
                     k, (int)s, what, J[1][1], JT[1][1], vJu, vJu2);
        n_derivative++;
        n_nonzero += nonzero;
    }
    printf("  derivative cases compared: %d (%d with a nonzero Jacobian)\n", n_derivative,
           n_nonzero);
    check(n_derivative >= 24 && n_nonzero >= n_derivative / 2 && bad_derivative == 0,
          "derivatives", "%d of %d cases off (%d with a nonzero Jacobian); first, %s",
          bad_derivative, n_derivative, n_nonzero, first_derivative);

    /* FMU state: get, step on with other inputs, set restores; serialized into a fresh instance. */
    const double A[4] = {5000.0, 0.08, -0.1, 0.02}, B[4] = {3000.0, -0.2, 0.3, -0.05};
    double saved[3], changed[3], restored[3];
    fmi3FMUState state = NULL, state2 = NULL;
    s = step(&ref, A, saved);
    double saved_t = ref.t;
    if (s == fmi3OK) s = fmi.GetFMUState(ref.c, &state);
    if (s == fmi3OK) s = step(&ref, B, changed);
    if (s == fmi3OK) s = fmi.SetFMUState(ref.c, state);
    if (s == fmi3OK) s = fmi.GetFloat64(ref.c, vr + FX, 3, restored, 3);
    check(s == fmi3OK && state && memcmp(saved, changed, sizeof saved) &&
              !memcmp(saved, restored, sizeof saved),
          "fmu_state_get_set",
          "status %d; Fy saved %.17g, after other inputs %.17g, restored %.17g",
          (int)s, saved[1], changed[1], restored[1]);
    ref.t = saved_t;

    size_t size = 0;
    fmi3Byte *bytes = NULL;
    Tire fresh = instantiate("fresh", token, resources);
    s = fresh.c ? initialize(&fresh, NULL) : fmi3Fatal;
    if (s == fmi3OK) s = step(&fresh, B, changed);
    if (s == fmi3OK) s = fmi.SerializedFMUStateSize(ref.c, state, &size);
    if (s == fmi3OK && size > 0 && (bytes = malloc(size)))
        s = fmi.SerializeFMUState(ref.c, state, bytes, size);
    if (s == fmi3OK && bytes) s = fmi.DeserializeFMUState(fresh.c, bytes, size, &state2);
    if (s == fmi3OK) s = fmi.SetFMUState(fresh.c, state2);
    if (s == fmi3OK) s = fmi.GetFloat64(fresh.c, vr + FX, 3, restored, 3);
    check(s == fmi3OK && bytes && !memcmp(saved, restored, sizeof saved), "fmu_state_serialize",
          "status %d, %zu bytes; Fy saved %.17g, in the fresh instance %.17g", (int)s, size,
          saved[1], restored[1]);
    free(bytes);
    fmi3Status s1 = fmi.FreeFMUState(ref.c, &state), s2 = fmi.FreeFMUState(fresh.c, &state2);
    check(s1 == fmi3OK && s2 == fmi3OK && !state && !state2, "fmu_state_free",
          "statuses %d %d, slots %p %p", (int)s1, (int)s2, state, state2);

    /* Hostile calls: errors, never crashes. */
    double x = 0.0, dx = 1.0, dy = 0.0;
    bool flag = false;
    fmi3FMUState none = NULL;
    const fmi3Status null_calls[] = {
        fmi.SetDebugLogging(NULL, true, 0, NULL),
        fmi.EnterInitializationMode(NULL, false, 0.0, 0.0, false, 0.0),
        fmi.ExitInitializationMode(NULL), fmi.GetFloat64(NULL, vr, 1, &x, 1),
        fmi.SetFloat64(NULL, vr, 1, &x, 1),
        fmi.DoStep(NULL, 0.0, H, false, &flag, &flag, &flag, &x),
        fmi.GetFMUState(NULL, &none), fmi.SerializedFMUStateSize(NULL, NULL, &size),
        fmi.GetDirectionalDerivative(NULL, vr + FX, 1, vr + FZ, 1, &dx, 1, &dy, 1),
        fmi.GetAdjointDerivative(NULL, vr + FX, 1, vr + FZ, 1, &dx, 1, &dy, 1),
        fmi.Terminate(NULL), fmi.Reset(NULL)};
    int n_null = sizeof null_calls / sizeof null_calls[0], null_ok = 0;
    for (int i = 0; i < n_null; i++) null_ok += null_calls[i] == fmi3Error;
    fmi.FreeInstance(NULL); /* a no-op */
    check(null_ok == n_null, "null_instance", "%d of %d calls returned fmi3Error", null_ok, n_null);

    mark = n_logged;
    Tire early = instantiate("early", token, resources);
    s = early.c ? fmi.DoStep(early.c, 0.0, H, false, &flag, &flag, &flag, &x) : fmi3Fatal;
    check(s == fmi3Error && logged_since(mark, fmi3Error, "fmi3DoStep", "Illegal call sequence"),
          "step_before_initialization", "status %d, or no message", (int)s);
    if (early.c) fmi.FreeInstance(early.c);

    mark = n_logged;
    double alpha_before = NAN, alpha_after = NAN, nan = NAN;
    fmi.GetFloat64(ref.c, &vr[ALPHA], 1, &alpha_before, 1);
    s = fmi.SetFloat64(ref.c, &vr[ALPHA], 1, &nan, 1);
    fmi.GetFloat64(ref.c, &vr[ALPHA], 1, &alpha_after, 1);
    check(s == fmi3Error && logged_since(mark, fmi3Error, "alpha", "NaN") == 1 &&
              alpha_after == alpha_before,
          "nan_input", "status %d, %d error messages naming alpha and NaN, alpha %.17g -> %.17g",
          (int)s, logged_since(mark, fmi3Error, "alpha", "NaN"), alpha_before, alpha_after);

    mark = n_logged;
    Tire wrong = instantiate("wrong_token", "{00000000-0000-0000-0000-000000000000}", resources);
    check(!wrong.c && logged_since(mark, fmi3Error, "does not match", ""), "wrong_token",
          "instance %p, or no message", wrong.c);
    if (wrong.c) fmi.FreeInstance(wrong.c);

    /* The end of a simulation. */
    s1 = fmi.Terminate(ref.c), s2 = fmi.Terminate(fresh.c);
    fmi3Status s3 = fmi.Terminate(params.c), s4 = fmi.Terminate(coef.c);
    check(s1 == fmi3OK && s2 == fmi3OK && s3 == fmi3OK && s4 == fmi3OK, "terminate",
          "statuses %d %d %d %d", (int)s1, (int)s2, (int)s3, (int)s4);
    fmi.FreeInstance(ref.c);
    fmi.FreeInstance(fresh.c);
    fmi.FreeInstance(params.c);
    fmi.FreeInstance(coef.c);
    check(1, "free_instance", ""); /* getting here without a crash is the check */
    check(FreeLibrary(dll), "free_library", "Windows error %lu", GetLastError());
    printf("  %d check(s) failed\n", failures);
    return failures ? 1 : 0;
}
