/* Model Exchange of a pdbfs FMU: the importer integrates; the event
 * indicators only mark kinks of the right-hand side (no discrete states). */
#include "fmu_instance.h"

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2EnterEventMode", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    m->s.mode = ST_EVENT;
    fmu_log(m, fmi2OK, "logEvents", "event mode at t=%.17g", m->s.time);
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2NewDiscreteStates", ST_EVENT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!info) return ERR(m, "fmi2NewDiscreteStates: NULL argument");
    /* no discrete states: the event indicators only mark kinks */
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2EnterContinuousTimeMode", ST_EVENT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    m->s.mode = ST_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    Inst *m = (Inst *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_check(m, "fmi2CompletedIntegratorStep", ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!enterEventMode || !terminateSimulation) return ERR(m, "fmi2CompletedIntegratorStep: NULL argument");
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2SetTime", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (!isfinite(time)) return ERR(m, "fmi2SetTime: time is not finite");
    m->s.time = time;
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2SetContinuousStates", ST_EVENT | ST_CONT, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2SetContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!x) return ERR(m, "fmi2SetContinuousStates: NULL argument");
    if (!fmu_all_finite(x, NX)) return ERR(m, "fmi2SetContinuousStates: state is not finite");
    for (i = 0; i < NX; i++) m->s.x[i] = x[i];
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2GetDerivatives", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetDerivatives: nx = %zu, expected %d", nx, NX);
    if (!derivatives) return ERR(m, "fmi2GetDerivatives: NULL argument");
    model_update(m);
    for (i = 0; i < NX; i++) derivatives[i] = m->xdot[i];
    if (!fmu_all_finite(m->xdot, NX)) return ERR(m, "fmi2GetDerivatives: derivatives are not finite at t=%g", m->s.time);
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real ind[], size_t ni) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2GetEventIndicators", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK)
        return fmi2Error;
    if (ni != NE) return ERR(m, "fmi2GetEventIndicators: ni = %zu, expected %d", ni, NE);
    if (ni > 0 && !ind) return ERR(m, "fmi2GetEventIndicators: NULL argument");
    model_update(m);
    for (i = 0; i < ni; i++) ind[i] = m->e[i];
    return fmi2OK;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    const double *xs;
    if (fmu_check(m, "fmi2GetContinuousStates", ST_ANY & ~ST_INSTANTIATED, fmi2ModelExchange) != fmi2OK)
        return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!x) return ERR(m, "fmi2GetContinuousStates: NULL argument");
    xs = model_x(m);
    for (i = 0; i < NX; i++) x[i] = xs[i];
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real nominals[], size_t nx) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2GetNominalsOfContinuousStates", ST_ANY, fmi2ModelExchange) != fmi2OK) return fmi2Error;
    if (nx != NX) return ERR(m, "fmi2GetNominalsOfContinuousStates: nx = %zu, expected %d", nx, NX);
    if (!nominals) return ERR(m, "fmi2GetNominalsOfContinuousStates: NULL argument");
    for (i = 0; i < NX; i++) nominals[i] = PDBFS_X_NOMINAL[i];
    return fmi2OK;
}
