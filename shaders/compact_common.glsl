// Shared by the compaction shaders (after CompactPush `push` is declared, with
// local_size_x = COMPACT_GROUP_SIZE): block addressing and one workgroup-wide exclusive scan.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

// Blocks lie on a 2D grid of workgroups: their count can exceed maxComputeWorkGroupCount[0].
uint blockIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// Subgroup arithmetic gives an ordered scan only when the subgroups tile the workgroup exactly
// (all full: then (subgroup, lane) enumerates 0..COMPACT_GROUP_SIZE-1 once each). Vulkan does not
// promise full subgroups without REQUIRE_FULL_SUBGROUPS, so this is checked, not assumed.
// Uniform across the workgroup: the barriers under it stay in uniform control flow.
bool useSubgroupScan() {
  return (push.mode & COMPACT_SHARED_SCAN) == 0u && gl_NumSubgroups * gl_SubgroupSize == COMPACT_GROUP_SIZE;
}

// This invocation's place in the scan order. Everything an invocation owns (its pixels, its mask
// word, its run of blocks) is addressed by its rank, so the order is defined here, not by how the
// driver happens to group invocations into subgroups.
uint scanRank() {
  return useSubgroupScan() ? gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID : gl_LocalInvocationIndex;
}

shared uint sScan[COMPACT_GROUP_SIZE];

// Sum of `value` over the invocations of lower rank; `total` gets the sum over the workgroup.
// Contains barriers: call from uniform control flow with every invocation of the group alive.
uint workgroupExclusiveAdd(uint value, out uint total) {
  if (useSubgroupScan()) {
    // One barrier: lanes scan in registers, subgroup totals meet in shared memory, and each
    // invocation adds up the (at most COMPACT_GROUP_SIZE / subgroup size) totals before its own.
    uint inclusive = subgroupInclusiveAdd(value);
    if (gl_SubgroupInvocationID == gl_SubgroupSize - 1u) sScan[gl_SubgroupID] = inclusive;
    barrier();
    uint before = 0u;
    total = 0u;
    for (uint s = 0u; s < gl_NumSubgroups; ++s) {
      uint t = sScan[s];
      before += s < gl_SubgroupID ? t : 0u;
      total += t;
    }
    barrier();  // sScan is reused by the next call
    return before + inclusive - value;
  }
  // Hillis-Steele inclusive scan in shared memory: log2(COMPACT_GROUP_SIZE) steps.
  uint i = gl_LocalInvocationIndex;
  sScan[i] = value;
  barrier();
  for (uint offset = 1u; offset < COMPACT_GROUP_SIZE; offset <<= 1) {
    uint add = i >= offset ? sScan[i - offset] : 0u;
    barrier();
    sScan[i] += add;
    barrier();
  }
  uint inclusive = sScan[i];
  total = sScan[COMPACT_GROUP_SIZE - 1u];
  barrier();
  return inclusive - value;
}
