/* What the FMI 2.0 and FMI 3.0 Windows harnesses (fmu_harness.c, fmu3_harness.c) share: the
 * kept log messages, the `ok`/`FAIL` checks, UTF-8 arguments, the NAME=VR arguments and the
 * reference tolerance. Header-only: each harness is one translation unit. */
#ifndef P87_HARNESS_H
#define P87_HARNESS_H

#include <windows.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- log: every message is kept (the last 256) and echoed, indented ---- */
typedef struct {
    char instance[32];
    int status;
    char text[1024];
} Message;
static Message logged[256];
static int n_logged;

/* Keeps a message the FMU logged (its text already formatted) and echoes it. */
static void keep_message(const char *instance, int status, const char *category,
                         const char *text) {
    Message *m = &logged[n_logged++ % 256];
    snprintf(m->text, sizeof m->text, "%s", text ? text : "(NULL)");
    snprintf(m->instance, sizeof m->instance, "%s", instance ? instance : "(NULL)");
    m->status = status;
    printf("  log %s [%d] %s: %s\n", m->instance, status, category ? category : "", m->text);
}

/* Messages logged since `mark` with at least `status` whose text contains both needles. */
static int logged_since(int mark, int status, const char *needle, const char *needle2) {
    int count = 0;
    for (int i = mark > n_logged - 256 ? mark : n_logged - 256; i < n_logged; i++) {
        const Message *m = &logged[i % 256];
        count += m->status >= status && strstr(m->text, needle) && strstr(m->text, needle2);
    }
    return count;
}

/* ---- checks ---- */
static int failures;

static void check(int ok, const char *name, const char *detail, ...) {
    if (ok) {
        printf("ok %s\n", name);
        return;
    }
    va_list args;
    va_start(args, detail);
    printf("FAIL %s: ", name);
    vprintf(detail, args);
    printf("\n");
    va_end(args);
    failures++;
}

static char *utf8(const wchar_t *w) {
    int n = WideCharToMultiByte(CP_UTF8, 0, w, -1, NULL, 0, NULL, NULL);
    char *s = malloc(n);
    WideCharToMultiByte(CP_UTF8, 0, w, -1, s, n, NULL, NULL);
    return s;
}

/* Reads the `n` arguments NAME=VR from argv[first], in the order of `names`, into `vr`;
 * 0, or 2 (the usage error's exit status) after saying which argument is wrong. */
static int read_references(wchar_t **argv, int first, const char *const *names, int n,
                           unsigned int *vr) {
    for (int i = 0; i < n; i++) {
        const char *arg = utf8(argv[first + i]), *eq = strchr(arg, '=');
        size_t len = strlen(names[i]);
        if (!eq || (size_t)(eq - arg) != len || strncmp(arg, names[i], len)) {
            fprintf(stderr, "argument %d: expected %s=VR, got %s\n", first + i, names[i], arg);
            return 2;
        }
        vr[i] = (unsigned int)strtoul(eq + 1, NULL, 10);
    }
    return 0;
}

/* Fx, Fy, Mz `out` equal to the reference `want` as magic_formula.assert_close has it: 1e-8
 * relative, floors 1 N and 0.01 N.m. */
static int matches_reference(const double out[3], const double want[3]) {
    int ok = 1;
    for (int j = 0; j < 3; j++) {
        double least = j == 2 ? 0.01 : 1.0;
        ok &= fabs(out[j] - want[j]) <= 1e-8 * fmax(fabs(want[j]), least);
    }
    return ok;
}

#endif
