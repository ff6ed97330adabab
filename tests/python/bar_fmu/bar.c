/* A split Hopkinson bar end as an FMI 2.0 co-simulation FMU, for the coupled-system test of
 * the Fractum FMU (tests/python/test_fmu.py): a semi-infinite elastic bar (density rho, wave
 * speed c, impedance Z = rho c) whose far end a striker of speed V hits at t = 0, sending the
 * incident pulse sigma_I = Z V / 2 for a duration T (V = 0: the transmitted bar). At the
 * specimen end, the stress sigma (input, compression positive) is the sum of the incident
 * and reflected waves, so the end moves into the specimen at v = (2 sigma_I - sigma) / Z.
 * Outputs are computed in fmi2DoStep from the input held over the step (no direct
 * feedthrough): v_into at t + h, v_away = -v_into, and the incident and reflected stresses. */
#include <stdlib.h>
#include <string.h>

typedef void *C;
typedef unsigned int VR;
typedef int St;
enum { OK = 0, ERR = 3 };
typedef struct {
    void (*logger)(void *, const char *, int, const char *, const char *, ...);
    void *(*alloc)(size_t, size_t);
    void (*freemem)(void *);
    void *step_finished;
    void *env;
} Callbacks;

/* value references: 0 stress (input), 1 v_into, 2 v_away, 3 incident, 4 reflected (outputs),
 * 5 density, 6 wave_speed, 7 striker_velocity, 8 pulse_duration (parameters) */
typedef struct { double v[9]; double t; } Bar;

static double incident(const Bar *b, double t) {
    return (t >= 0 && t < b->v[8]) ? 0.5 * b->v[5] * b->v[6] * b->v[7] : 0.0;
}
static void outputs(Bar *b, double t) {
    double z = b->v[5] * b->v[6], si = incident(b, t);
    b->v[1] = (2 * si - b->v[0]) / z;
    b->v[2] = -b->v[1];
    b->v[3] = si;
    b->v[4] = b->v[0] - si;
}

const char *fmi2GetTypesPlatform(void) { return "default"; }
const char *fmi2GetVersion(void) { return "2.0"; }
C fmi2Instantiate(const char *n, int k, const char *g, const char *r, const Callbacks *cb, int vis, int log) {
    Bar *b = calloc(1, sizeof *b);
    if (!b) return NULL;
    b->v[5] = 7850; b->v[6] = 5000; b->v[7] = 0; b->v[8] = 1e-4;
    outputs(b, 0);
    return b;
}
void fmi2FreeInstance(C c) { free(c); }
St fmi2SetDebugLogging(C c, int on, size_t n, const char *const *cat) { return OK; }
St fmi2SetupExperiment(C c, int tol, double t, double start, int stopdef, double stop) { ((Bar *)c)->t = start; return OK; }
St fmi2EnterInitializationMode(C c) { return OK; }
St fmi2ExitInitializationMode(C c) { outputs(c, ((Bar *)c)->t); return OK; }
St fmi2Terminate(C c) { return OK; }
St fmi2Reset(C c) { return ERR; }
St fmi2GetReal(C c, const VR *vr, size_t n, double *x) {
    for (size_t i = 0; i < n; i++) { if (vr[i] > 8) return ERR; x[i] = ((Bar *)c)->v[vr[i]]; }
    return OK;
}
St fmi2SetReal(C c, const VR *vr, size_t n, const double *x) {
    for (size_t i = 0; i < n; i++) { if (vr[i] > 8 || vr[i] == 1 || vr[i] == 2 || vr[i] == 3 || vr[i] == 4) return ERR; ((Bar *)c)->v[vr[i]] = x[i]; }
    return OK;
}
St fmi2DoStep(C c, double t, double h, int noprior) {
    Bar *b = c;
    b->t = t + h;
    outputs(b, b->t);
    return OK;
}
#define NO(name, ...) St name(__VA_ARGS__) { return ERR; }
NO(fmi2GetInteger, C c, const VR *vr, size_t n, int *x)
NO(fmi2GetBoolean, C c, const VR *vr, size_t n, int *x)
NO(fmi2GetString, C c, const VR *vr, size_t n, const char **x)
NO(fmi2SetInteger, C c, const VR *vr, size_t n, const int *x)
NO(fmi2SetBoolean, C c, const VR *vr, size_t n, const int *x)
NO(fmi2SetString, C c, const VR *vr, size_t n, const char *const *x)
NO(fmi2GetFMUstate, C c, void **s)
NO(fmi2SetFMUstate, C c, void *s)
NO(fmi2FreeFMUstate, C c, void **s)
NO(fmi2SerializedFMUstateSize, C c, void *s, size_t *n)
NO(fmi2SerializeFMUstate, C c, void *s, char *b, size_t n)
NO(fmi2DeSerializeFMUstate, C c, const char *b, size_t n, void **s)
NO(fmi2GetDirectionalDerivative, C c, const VR *a, size_t na, const VR *b, size_t nb, const double *dv, double *df)
NO(fmi2SetRealInputDerivatives, C c, const VR *vr, size_t n, const int *o, const double *x)
NO(fmi2GetRealOutputDerivatives, C c, const VR *vr, size_t n, const int *o, double *x)
NO(fmi2CancelStep, C c)
NO(fmi2GetStatus, C c, int k, int *s)
NO(fmi2GetRealStatus, C c, int k, double *s)
NO(fmi2GetIntegerStatus, C c, int k, int *s)
NO(fmi2GetBooleanStatus, C c, int k, int *s)
NO(fmi2GetStringStatus, C c, int k, const char **s)
