/* The Model Exchange and Co-Simulation calls of FMI 2.0 on the
 * version-neutral model_exchange.c and cosimulation.c. */
#include <math.h>

#include "fmi2_prefix.h"
#include "fmu_instance.h"

/* ------------------------------------------------------- Model Exchange */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    return me_enter_event_mode((Inst *)c, "fmi2EnterEventMode");
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Inst *m = (Inst *)c;
    if (me_new_discrete_states(m, "fmi2NewDiscreteStates") != fmi2OK) return fmi2Error;
    if (!info) return ERR(m, "fmi2NewDiscreteStates: NULL argument");
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTime = me_next_event_time(m);      /* a valve's switch: a time event */
    info->nextEventTimeDefined = isfinite(info->nextEventTime) ? fmi2True : fmi2False;
    if (!info->nextEventTimeDefined) info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    return me_enter_continuous_mode((Inst *)c, "fmi2EnterContinuousTimeMode");
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    Inst *m = (Inst *)c;
    int enter, term;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (me_completed_step(m, "fmi2CompletedIntegratorStep", &enter, &term) != fmi2OK) return fmi2Error;
    if (!enterEventMode || !terminateSimulation) return ERR(m, "fmi2CompletedIntegratorStep: NULL argument");
    *enterEventMode = enter ? fmi2True : fmi2False;
    *terminateSimulation = term ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    return me_set_time((Inst *)c, "fmi2SetTime", time);
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    return me_set_states((Inst *)c, "fmi2SetContinuousStates", x, nx);
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    return me_get_derivatives((Inst *)c, "fmi2GetDerivatives", derivatives, nx);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real ind[], size_t ni) {
    return me_get_event_indicators((Inst *)c, "fmi2GetEventIndicators", ind, ni);
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    return me_get_states((Inst *)c, "fmi2GetContinuousStates", x, nx);
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real nominals[], size_t nx) {
    return me_get_nominals((Inst *)c, "fmi2GetNominalsOfContinuousStates", nominals, nx);
}

/* -------------------------------------------------------- Co-Simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2SetRealInputDerivatives", ST_INSTANTIATED | ST_INIT | ST_STEPDONE, fmi2CoSimulation) !=
        fmi2OK)
        return fmi2Error;
    /* canInterpolateInputs: each input runs linearly from the current communication point */
    return (fmi2Status)values_set_input_slopes(m, "fmi2SetRealInputDerivatives", vr, nvr, order, value);
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2GetRealOutputDerivatives", ST_STEPDONE | ST_TERMINATED, fmi2CoSimulation) != fmi2OK)
        return fmi2Error;
    return (fmi2Status)deriv_outputs(m, "fmi2GetRealOutputDerivatives", vr, nvr, order, value);
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Inst *m = (Inst *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_check(m, "fmi2DoStep", ST_STEPDONE, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return cosim_do_step(m, "fmi2DoStep", t, h, NULL);
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2CancelStep", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return ERR(m, "fmi2CancelStep: fmi2DoStep never runs asynchronously");
}

/* the status calls: only the last successful time and 'not terminated' are known */
#define STATUS_CALL(NAME, TYPE, KIND, VALUE)                                                     \
    fmi2Status NAME(fmi2Component c, const fmi2StatusKind s, TYPE *value) {                    \
        Inst *m = (Inst *)c;                                                                   \
        if (fmu_check(m, #NAME, ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;         \
        if ((int)s == (int)(KIND) && value) {                                                  \
            *value = (VALUE);                                                                  \
            return fmi2OK;                                                                     \
        }                                                                                      \
        return fmi2Discard;                                                                    \
    }

STATUS_CALL(fmi2GetStatus, fmi2Status, -1, fmi2OK)
STATUS_CALL(fmi2GetRealStatus, fmi2Real, fmi2LastSuccessfulTime, m->s.time)
STATUS_CALL(fmi2GetIntegerStatus, fmi2Integer, -1, 0)
STATUS_CALL(fmi2GetBooleanStatus, fmi2Boolean, fmi2Terminated, fmi2False)
STATUS_CALL(fmi2GetStringStatus, fmi2String, -1, "")
