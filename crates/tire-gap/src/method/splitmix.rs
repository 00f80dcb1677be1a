//! SplitMix64: the small deterministic generator behind every seeded choice outside the
//! synthetic data's ChaCha8 streams (fold deals, tie orders, permutation and sign-flip draws)
//! and behind the keys of those streams, so results are the same on every platform.

/// Advances `state` by the golden-ratio increment and returns the mixed value.
pub fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_sequence_from_zero() {
        // The first outputs of the published SplitMix64 seeded with 0.
        let mut state = 0;
        assert_eq!(splitmix64(&mut state), 0xe220_a839_7b1d_cdaf);
        assert_eq!(splitmix64(&mut state), 0x6e78_9e6a_a1b9_65f4);
        assert_eq!(splitmix64(&mut state), 0x06c4_5d18_8009_454f);
        assert_eq!(state, 0x9e37_79b9_7f4a_7c15_u64.wrapping_mul(3));
    }
}
