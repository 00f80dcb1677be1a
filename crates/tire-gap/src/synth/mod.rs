//! Synthetic test-rig data from a tire that is not the paper's, with chosen effects switched on.
