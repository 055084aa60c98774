//! The shapes of compute dispatches that every device accepts.

/// Workgroups one dimension of a dispatch may have on every device (Vulkan's required minimum
/// of maxComputeWorkGroupCount).
pub const MAX_WORKGROUPS_X: u32 = 65_535;

/// The threads of a pass of `groups` workgroups of `workgroup` threads in a line, laid out in
/// rows of at most [`MAX_WORKGROUPS_X`] workgroups (the shader rebuilds its index from x and y:
/// `gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x`). At least one workgroup.
pub fn rows_of_workgroups(groups: u32, workgroup: u32) -> [u32; 3] {
    let groups = groups.max(1);
    let columns = groups.min(MAX_WORKGROUPS_X);
    [columns * workgroup, groups.div_ceil(columns), 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_hold_every_workgroup_and_stay_within_the_limit() {
        assert_eq!(rows_of_workgroups(0, 64), [64, 1, 1]);
        assert_eq!(rows_of_workgroups(1000, 64), [64_000, 1, 1]);
        assert_eq!(
            rows_of_workgroups(MAX_WORKGROUPS_X, 32),
            [MAX_WORKGROUPS_X * 32, 1, 1]
        );
        assert_eq!(
            rows_of_workgroups(MAX_WORKGROUPS_X + 1, 1),
            [MAX_WORKGROUPS_X, 2, 1]
        );
        for groups in [1, 7, 65_534, 65_536, 200_000, 10_000_000, u32::MAX] {
            let [x, y, z] = rows_of_workgroups(groups, 1);
            assert!(x <= MAX_WORKGROUPS_X && z == 1);
            let covered = u64::from(x) * u64::from(y);
            // Every workgroup, and less than one row more.
            assert!(covered >= u64::from(groups) && covered < u64::from(groups) + u64::from(x));
        }
    }
}
