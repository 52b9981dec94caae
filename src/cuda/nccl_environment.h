// The process environment NCCL reads when its first communicator is made, set in one place for every
// NCCL user in corebox (the NCCL exchange of the multi-GPU backend and `corebox bench p2p`).
//
// Design note. NCCL reads its NCCL_* variables once, at the first call that initialises it, so this
// must run before the first ncclCommInitAll (or any other NCCL call) of the process; calling it again
// is harmless. A value the user has already set is never overridden, so a machine that does have
// NVLink SHARP can still turn it on with NCCL_NVLS_ENABLE=1.
#pragma once

namespace corebox {

// Sets NCCL_NVLS_ENABLE=0 unless the variable is already set. NVLink SHARP (NVLS) multicast is not
// available on the multi-GPU machines corebox is measured on: NCCL turns it on by itself on NVSwitch
// hosts, and a process using it there can take the host's shared GPUs out of service. An all-gather
// of a few MB gains nothing from it anyway.
void prepareNcclEnvironment();

}  // namespace corebox
