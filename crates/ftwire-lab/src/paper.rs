//! The paper's published results that the experiments print beside their own and that
//! `ftwire reproduce` tabulates: Table I (identification), Table II (shape from F/T), Table III
//! (goal reaching) and Table IV (tracking). One copy, read by the experiments and by
//! [`crate::beside`].

/// One parameter's row of Table I: the true value, the estimated mean, its ±, and the relative
/// error \[%\]; stiffnesses in N·m², the length in m.
pub type PaperRow = (f64, f64, f64, f64);

/// Table I of the paper, identification from 3 samples: `(wire, rows of c1, c2, c3, L)`.
pub const TABLE_I: [(&str, [PaperRow; 4]); 2] = [
    (
        "nitinol-2mm-630",
        [
            (0.042, 0.043, 0.006, 2.4),
            (0.055, 0.056, 0.008, 1.8),
            (0.055, 0.056, 0.008, 1.8),
            (0.630, 0.635, 0.012, 0.8),
        ],
    ),
    (
        "nitinol-3mm-820",
        [
            (0.214, 0.215, 0.008, 0.5),
            (0.278, 0.279, 0.011, 0.4),
            (0.278, 0.279, 0.011, 0.4),
            (0.820, 0.811, 0.013, 1.1),
        ],
    ),
];

/// Table II of the paper: the mean shape error \[mm\] from F/T of the real wires,
/// `(wire, error)`.
pub const TABLE_II: [(&str, f64); 4] = [
    ("nitinol-2mm-630", 5.72),
    ("nitinol-3mm-910", 7.42),
    ("nitinol-3mm-820", 6.55),
    ("cable-3mm-920", 52.3),
];

/// Table III of the paper: the mean shape error \[mm\] at the end of a motion to a goal in
/// `A`, `(variant, open loop, closed loop)`, the variant named as in the goal experiment's
/// summary (`no_noise`, `noise`: the paper's gripper noise, `increment`).
pub const TABLE_III: [(&str, f64, f64); 2] = [("no_noise", 4.80, 9.67), ("noise", 17.35, 9.11)];

/// Table IV of the paper: the shape error \[mm\] along a path planned with RRT* and tracked
/// under its noise, `(open loop mean, closed loop mean, closed loop std)`; beside
/// [`crate::track`]'s results.
pub const TABLE_IV: (f64, f64, f64) = (11.01, 6.22, 1.83);

/// The passage of the paper's §IV-E: successes of [`PASSAGE_ATTEMPTS`] attempts of each mode
/// under its noise (`increment`), `(open loop, closed loop)`; beside [`crate::passage`]'s
/// results.
pub const PASSAGE_SUCCESSES: (usize, usize) = (3, 9);

/// Attempts of each mode in the paper's passage (§IV-E).
pub const PASSAGE_ATTEMPTS: usize = 10;
