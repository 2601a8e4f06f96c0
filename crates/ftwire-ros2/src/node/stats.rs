//! What a node measures of its stream: samples lost by the stamp sequence, and latencies.

use serde::Serialize;

/// Counts the samples a stream of stamps `k / rate` skipped: the `k` of each stamp is
/// `round(t · rate)`, and a gap between consecutive `k` is that many samples lost (on the
/// way, or by the sensor's dropouts). A stamp not after the previous one is out of order.
///
/// # Example
/// ```
/// use ftwire_ros2::node::stats::LossCounter;
/// let mut loss = LossCounter::new(1000.0);
/// for t in [0.010, 0.011, 0.014, 0.013] {
///     loss.add(t);
/// }
/// assert_eq!((loss.lost(), loss.out_of_order()), (2, 1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LossCounter {
    rate: f64,
    last: Option<i64>,
    first: Option<i64>,
    lost: u64,
    out_of_order: u64,
}

impl LossCounter {
    /// A counter for a clock at `rate` \[Hz\].
    pub fn new(rate: f64) -> Self {
        Self {
            rate,
            last: None,
            first: None,
            lost: 0,
            out_of_order: 0,
        }
    }

    /// Takes the stamp `t` \[s\] of the next sample received, and returns its index `k`.
    pub fn add(&mut self, t: f64) -> i64 {
        #[allow(clippy::cast_possible_truncation)] // stamps far below 2⁶³ ticks
        let k = (t * self.rate).round() as i64;
        match self.last {
            Some(last) if k <= last => self.out_of_order += 1,
            Some(last) => {
                self.lost += (k - last - 1).unsigned_abs();
                self.last = Some(k);
            }
            None => {
                self.first = Some(k);
                self.last = Some(k);
            }
        }
        k
    }

    /// Samples skipped between the first and the last received.
    pub fn lost(&self) -> u64 {
        self.lost
    }

    /// Samples not after the one before.
    pub fn out_of_order(&self) -> u64 {
        self.out_of_order
    }

    /// The index of the first sample received.
    pub fn first(&self) -> Option<i64> {
        self.first
    }

    /// The largest index received (`k / rate` the newest stamp).
    pub fn last(&self) -> Option<i64> {
        self.last
    }
}

/// Median, 99th percentile and largest of a set of times \[ms\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Spread {
    /// How many.
    pub count: usize,
    /// Median \[ms\].
    pub median: f64,
    /// 99th percentile (nearest rank) \[ms\].
    pub p99: f64,
    /// Largest \[ms\].
    pub max: f64,
}

impl Spread {
    /// The spread of `values` \[ms\] (sorted in place); `None` when empty.
    ///
    /// # Example
    /// ```
    /// use ftwire_ros2::node::stats::Spread;
    /// let mut v: Vec<f64> = (1..=100).map(f64::from).collect();
    /// let s = Spread::of(&mut v).ok_or("values")?;
    /// assert_eq!((s.median, s.p99, s.max), (50.0, 99.0, 100.0));
    /// # Ok::<(), &str>(())
    /// ```
    pub fn of(values: &mut [f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        values.sort_by(f64::total_cmp);
        let n = values.len();
        #[allow(
            clippy::cast_precision_loss,
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss
        )]
        let rank = |q: f64| ((q * n as f64).ceil() as usize).clamp(1, n) - 1;
        Some(Self {
            count: n,
            median: values[rank(0.5)],
            p99: values[rank(0.99)],
            max: values[n - 1],
        })
    }
}
