/* The Model Exchange and Co-Simulation calls of FMI 3.0 on the
 * version-neutral model_exchange.c and cosimulation.c (the same CVODE loop
 * as FMI 2.0).  Co-Simulation has no event mode: fmi3DoStep integrates
 * through the rig's events itself, calling the importer's intermediate
 * update after each internal step, and returns early where it asks. */
#include <math.h>

#include "fmi3Functions.h"
#include "fmu_instance.h"

/* ------------------------------------------------------- Model Exchange */

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    return me_enter_event_mode((Inst *)instance, "fmi3EnterEventMode");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    Inst *m = (Inst *)instance;
    if (me_new_discrete_states(m, "fmi3UpdateDiscreteStates") != FMU_OK) return fmi3Error;
    /* no discrete states: nothing changes at an event */
    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = fmi3False;
    if (terminateSimulation) *terminateSimulation = fmi3False;
    if (nominalsOfContinuousStatesChanged) *nominalsOfContinuousStatesChanged = fmi3False;
    if (valuesOfContinuousStatesChanged) *valuesOfContinuousStatesChanged = fmi3False;
    {   /* a valve's switch: a time event */
        double next = me_next_event_time(m);
        if (nextEventTimeDefined) *nextEventTimeDefined = isfinite(next) ? fmi3True : fmi3False;
        if (nextEventTime) *nextEventTime = isfinite(next) ? next : 0.0;
    }
    return fmi3OK;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    return me_enter_continuous_mode((Inst *)instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation) {
    Inst *m = (Inst *)instance;
    int enter, term;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (me_completed_step(m, "fmi3CompletedIntegratorStep", &enter, &term) != FMU_OK) return fmi3Error;
    if (!enterEventMode || !terminateSimulation) return ERR(m, "fmi3CompletedIntegratorStep: NULL argument");
    *enterEventMode = enter != 0;
    *terminateSimulation = term != 0;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    return me_set_time((Inst *)instance, "fmi3SetTime", time);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx) {
    return me_set_states((Inst *)instance, "fmi3SetContinuousStates", x, nx);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nx) {
    return me_get_derivatives((Inst *)instance, "fmi3GetContinuousStateDerivatives", derivatives, nx);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t ni) {
    return me_get_event_indicators((Inst *)instance, "fmi3GetEventIndicators", indicators, ni);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx) {
    return me_get_states((Inst *)instance, "fmi3GetContinuousStates", x, nx);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nx) {
    return me_get_nominals((Inst *)instance, "fmi3GetNominalsOfContinuousStates", nominals, nx);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n) {
    Inst *m = (Inst *)instance;
    if (fmu_check(m, "fmi3GetNumberOfEventIndicators", ST_ANY, FMU_ME) != FMU_OK) return fmi3Error;
    if (!n) return ERR(m, "fmi3GetNumberOfEventIndicators: NULL argument");
    *n = NE;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n) {
    Inst *m = (Inst *)instance;
    if (fmu_check(m, "fmi3GetNumberOfContinuousStates", ST_ANY, FMU_ME) != FMU_OK) return fmi3Error;
    if (!n) return ERR(m, "fmi3GetNumberOfContinuousStates: NULL argument");
    *n = NX;
    return fmi3OK;
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    Inst *m = (Inst *)instance;
    if (fmu_check(m, "fmi3EvaluateDiscreteStates", ST_ANY, -1) != FMU_OK) return fmi3Error;
    return ERR(m, "fmi3EvaluateDiscreteStates: not provided (providesEvaluateDiscreteStates=false)");
}

/* -------------------------------------------------------- Co-Simulation */

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    Inst *m = (Inst *)instance;
    if (fmu_check(m, "fmi3EnterStepMode", ST_ANY, FMU_CS) != FMU_OK) return fmi3Error;
    return ERR(m, "fmi3EnterStepMode: the FMU has no event mode (hasEventMode=false)");
}

_Static_assert(sizeof(fmi3Int32) == sizeof(int), "an order is an int");

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                    const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues) {
    Inst *m = (Inst *)instance;
    const char *fn = "fmi3GetOutputDerivatives";
    if (fmu_check(m, fn, ST_STEPDONE | ST_TERMINATED | ST_INTERMEDIATE, FMU_CS) != FMU_OK) return fmi3Error;
    if (nValues != nvr) return ERR(m, "%s: nValues = %zu, expected %zu (all variables are scalars)", fn, nValues, nvr);
    return (fmi3Status)deriv_outputs(m, fn, vr, nvr, (const int *)orders, values);
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime) {
    Inst *m = (Inst *)instance;
    int st, early = 0;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_check(m, "fmi3DoStep", ST_STEPDONE, FMU_CS) != FMU_OK) return fmi3Error;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return ERR(m, "fmi3DoStep: NULL argument");
    st = cosim_do_step(m, "fmi3DoStep", t, h, &early);
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = early ? fmi3True : fmi3False;   /* (asked in an intermediate update) */
    *lastSuccessfulTime = m->s.time;
    return (fmi3Status)st;
}

/* -------------------------------------------------- Scheduled Execution */

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    Inst *m = (Inst *)instance;
    (void)clockReference; (void)activationTime;
    if (fmu_check(m, "fmi3ActivateModelPartition", ST_ANY, -1) != FMU_OK) return fmi3Error;
    return ERR(m, "fmi3ActivateModelPartition: the FMU offers no Scheduled Execution");
}
