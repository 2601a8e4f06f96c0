//! The values a front end is given as text (a command-line option, a ROS parameter, a line
//! of a settings file), parsed and checked the same way everywhere: vectors of finite numbers,
//! rotation vectors, scalars, and counts within a stated range.
//!
//! Vectors are comma separated, `X,Y,Z`, with a leading minus sign allowed; every component
//! must be a finite number, so `nan` and `inf` are refused. A rotation vector's norm (its
//! angle) is at most `ftwire_core::MAX_ROTATION_ANGLE` ([`parse_rotation`]). The `ftwire`
//! binary turns each error into clap's, naming the option (exit 2).

use serde::Serialize;

/// `N` finite numbers given as one comma-separated option value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Numbers<const N: usize>(pub [f64; N]);

/// Serialised as a JSON array of `N` numbers (serde derives arrays only up to 32, not for `N`).
impl<const N: usize> Serialize for Numbers<N> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.as_slice().serialize(serializer)
    }
}

/// Three numbers, e.g. a position `X,Y,Z` \[m\] or a rotation vector `RX,RY,RZ` \[rad\].
pub type Vec3 = Numbers<3>;
/// Six numbers, e.g. a configuration `a = (τ1,τ2,τ3,f1,f2,f3)`.
pub type Vec6 = Numbers<6>;
/// Seven numbers, e.g. the joint angles of one SDA10F arm \[rad\].
pub type Vec7 = Numbers<7>;

impl<const N: usize> Numbers<N> {
    /// As a nalgebra vector.
    pub fn to_vector(&self) -> nalgebra::SVector<f64, N> {
        nalgebra::SVector::from(self.0)
    }
}

/// The value parser of every vector option: `N` comma-separated finite numbers. The error
/// text is the same for every option (clap prefixes the option's name):
/// `expected 3 comma-separated finite numbers, got "1,x,3" ("x" is not a number)`.
///
/// # Errors
/// A wrong count, a part that is not a number, or a non-finite number.
///
/// # Example
/// ```
/// use ftwire_app::input::parse_numbers;
/// assert_eq!(parse_numbers::<3>("-0.5,0.1,0").map(|v| v.0), Ok([-0.5, 0.1, 0.0]));
/// assert!(parse_numbers::<3>("1,nan,0").is_err());
/// ```
pub fn parse_numbers<const N: usize>(text: &str) -> Result<Numbers<N>, String> {
    let fail = |why: String| {
        format!("expected {N} comma-separated finite numbers, got \"{text}\" ({why})")
    };
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(fail(format!("{} values", parts.len())));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(&parts) {
        *slot = parse_finite(part).map_err(fail)?;
    }
    Ok(Numbers(out))
}

/// The value parser of every rotation-vector option (`RX,RY,RZ`, axis × angle \[rad\]): three
/// finite numbers whose norm, the angle, is at most `ftwire_core::MAX_ROTATION_ANGLE` (10⁶ rad;
/// its docs say why).
///
/// # Errors
/// As [`parse_numbers`], or an angle beyond the bound, with the value and the bound.
///
/// # Example
/// ```
/// use ftwire_app::input::parse_rotation;
/// assert_eq!(parse_rotation("0,0,-3.1").map(|v| v.0), Ok([0.0, 0.0, -3.1]));
/// let e = parse_rotation("1e300,0,0").expect_err("too large");
/// assert!(e.contains("1e300") && e.contains("1e6 rad"), "{e}");
/// ```
pub fn parse_rotation(text: &str) -> Result<Vec3, String> {
    let rotation = parse_numbers::<3>(text)?;
    ftwire_core::ensure_rotation_vector("RX,RY,RZ", &rotation.0).map_err(|e| e.to_string())?;
    Ok(rotation)
}

/// The value parser of every scalar option: one finite number (a leading minus allowed).
///
/// # Errors
/// Not a number, or not finite.
pub fn parse_finite(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("\"{text}\" is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("\"{text}\" is not a finite number"))
    }
}

/// The allowed range of a whole-number option (a count: trials, samples, nodes), checked by
/// its value parser before any work, so that no count can ask for more memory or time than
/// the range's reasoning allows. Each option states its range in its `--help` text. The error
/// names the option, the value and the range (clap exits 2):
/// `--pairs 0: at least 1 and at most 10000`.
///
/// # Example
/// ```
/// use ftwire_app::input::CountRange;
/// const PAIRS: CountRange = CountRange::new(1, 10_000);
/// assert_eq!(PAIRS.check("--pairs", "30"), Ok(30));
/// assert_eq!(PAIRS.check("--pairs", "0").unwrap_err(), "--pairs 0: at least 1 and at most 10000");
/// assert!(PAIRS.check("--pairs", "-1").is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CountRange {
    /// The smallest value allowed.
    pub min: usize,
    /// The largest value allowed.
    pub max: usize,
}

impl CountRange {
    /// The range `min..=max`.
    pub const fn new(min: usize, max: usize) -> Self {
        Self { min, max }
    }

    /// Whether `value` is in the range.
    pub fn contains(&self, value: usize) -> bool {
        (self.min..=self.max).contains(&value)
    }

    /// `value` checked against the range; `name` (e.g. `--pairs`, or `"nodes"` of a batch
    /// line) names it in the error.
    ///
    /// # Errors
    /// Not a whole number, or outside the range.
    pub fn check_value(&self, name: &str, value: usize) -> Result<usize, String> {
        if self.contains(value) {
            Ok(value)
        } else {
            Err(format!(
                "{name} {value}: at least {} and at most {}",
                self.min, self.max
            ))
        }
    }

    /// `text` parsed and checked against the range; `name` names it in the error.
    ///
    /// # Errors
    /// Not a whole number, or outside the range.
    pub fn check(&self, name: &str, text: &str) -> Result<usize, String> {
        let trimmed = text.trim();
        match trimmed.parse::<usize>() {
            Ok(value) => self.check_value(name, value),
            // All digits but too large for the machine: out of range all the same.
            Err(_) if !trimmed.is_empty() && trimmed.bytes().all(|b| b.is_ascii_digit()) => {
                Err(format!(
                    "{name} {trimmed}: at least {} and at most {}",
                    self.min, self.max
                ))
            }
            Err(_) => Err(format!(
                "{name} {text:?}: not a whole number (at least {} and at most {})",
                self.min, self.max
            )),
        }
    }
}

impl std::fmt::Display for Numbers<3> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x, y, z] = self.0;
        write!(f, "{x},{y},{z}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_parse_with_signs_and_say_what_is_wrong() {
        assert_eq!(
            parse_numbers::<3>("1, -2,3e-1").map(|v| v.0),
            Ok([1.0, -2.0, 0.3])
        );
        assert_eq!(
            parse_numbers::<6>("-0,-1,-2,-3,-4,-5").map(|v| v.0),
            Ok([-0.0, -1.0, -2.0, -3.0, -4.0, -5.0])
        );
        let e = parse_numbers::<7>("1,2,3").expect_err("too few");
        assert_eq!(
            e,
            "expected 7 comma-separated finite numbers, got \"1,2,3\" (3 values)"
        );
        let e = parse_numbers::<3>("1,x,3").expect_err("not a number");
        assert!(e.contains("\"x\" is not a number"), "{e}");
        for bad in ["1,NaN,3", "inf,0,0", "0,0,-inf"] {
            let e = parse_numbers::<3>(bad).expect_err("not finite");
            assert!(e.contains("not a finite number"), "{e}");
        }
        assert_eq!(parse_finite("-0.3"), Ok(-0.3));
        assert!(parse_finite("nan").is_err());
    }
}
