/* FMU state of a pdbfs FMU through FMI 3.0 (snapshot.c), and the optional
 * FMI 3.0 calls it does not offer (dependencies at run time, derivatives,
 * configuration mode, clocks): each answers fmi3Error with a log line. */
#include "fmi3Functions.h"
#include "fmu_instance.h"

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state) {
    return snapshot_get((Inst *)instance, "fmi3GetFMUState", state);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state) {
    return snapshot_set((Inst *)instance, "fmi3SetFMUState", state);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state) {
    return snapshot_free((Inst *)instance, state);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size) {
    return snapshot_size((Inst *)instance, "fmi3SerializedFMUStateSize", state, size);
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size) {
    return snapshot_serialize((Inst *)instance, "fmi3SerializeFMUState", state, bytes, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size,
                                   fmi3FMUState *state) {
    return snapshot_deserialize((Inst *)instance, "fmi3DeserializeFMUState", bytes, size, state);
}

/* a call the FMU does not offer: the modelDescription.xml says so too */
static fmi3Status not_provided(fmi3Instance instance, const char *fn, const char *why) {
    Inst *m = (Inst *)instance;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return fmi3Error;
    return ERR(m, "%s: not provided (%s)", fn, why);
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    (void)valueReference; (void)nDependencies;
    return not_provided(instance, "fmi3GetNumberOfVariableDependencies", "see ModelStructure");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return not_provided(instance, "fmi3GetVariableDependencies", "see ModelStructure");
}

/* scalar variables only: one seed per known (directional) or unknown (adjoint) */
#define DERIVATIVE_CALL(NAME, FN, NSEED, NSENS)                                                            \
    fmi3Status NAME(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,          \
                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, \
                    fmi3Float64 sensitivity[], size_t nSensitivity) {                                       \
        Inst *m = (Inst *)instance;                                                                        \
        if (fmu_check(m, #NAME, ST_ANY, -1) != FMU_OK) return fmi3Error;                                   \
        if (nSeed != (NSEED) || nSensitivity != (NSENS))                                                   \
            return (fmi3Status)ERR(m, "%s: nSeed = %zu and nSensitivity = %zu, expected %zu and %zu", #NAME, \
                                   nSeed, nSensitivity, (size_t)(NSEED), (size_t)(NSENS));                 \
        return (fmi3Status)FN(m, #NAME, unknowns, nUnknowns, knowns, nKnowns, seed, sensitivity);          \
    }

DERIVATIVE_CALL(fmi3GetDirectionalDerivative, deriv_forward, nKnowns, nUnknowns)
DERIVATIVE_CALL(fmi3GetAdjointDerivative, deriv_adjoint, nUnknowns, nKnowns)

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    return not_provided(instance, "fmi3EnterConfigurationMode", "the FMU has no structural parameters");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    return not_provided(instance, "fmi3ExitConfigurationMode", "the FMU has no structural parameters");
}

#define NO_CLOCKS "the FMU has no clocks"

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]) {
    (void)vr; (void)nvr; (void)intervals; (void)qualifiers;
    return not_provided(instance, "fmi3GetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[]) {
    (void)vr; (void)nvr; (void)counters; (void)resolutions; (void)qualifiers;
    return not_provided(instance, "fmi3GetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               fmi3Float64 shifts[]) {
    (void)vr; (void)nvr; (void)shifts;
    return not_provided(instance, "fmi3GetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[]) {
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    return not_provided(instance, "fmi3GetShiftFraction", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  const fmi3Float64 intervals[]) {
    (void)vr; (void)nvr; (void)intervals;
    return not_provided(instance, "fmi3SetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    return not_provided(instance, "fmi3SetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               const fmi3Float64 shifts[]) {
    (void)vr; (void)nvr; (void)shifts;
    return not_provided(instance, "fmi3SetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
    (void)vr; (void)nvr; (void)counters; (void)resolutions;
    return not_provided(instance, "fmi3SetShiftFraction", NO_CLOCKS);
}
