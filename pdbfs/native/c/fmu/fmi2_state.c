/* FMU state of a pdbfs FMU through FMI 2.0: snapshot.c (a plain copy of
 * time, states, parameters and settings; CVODE restarts from a restored
 * state). */
#include "fmi2_prefix.h"
#include "fmu_instance.h"

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    return snapshot_get((Inst *)c, "fmi2GetFMUstate", state);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    return snapshot_set((Inst *)c, "fmi2SetFMUstate", state);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    return snapshot_free((Inst *)c, state);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    return snapshot_size((Inst *)c, "fmi2SerializedFMUstateSize", state, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
    return snapshot_serialize((Inst *)c, "fmi2SerializeFMUstate", state, (unsigned char *)bytes, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state) {
    return snapshot_deserialize((Inst *)c, "fmi2DeSerializeFMUstate", (const unsigned char *)bytes, size, state);
}
