//! The total potential energy of the rod and its exact derivatives.
//!
//! Degrees of freedom are interleaved per node, `(x_k, y_k, z_k, θ_k)` for `k = 0..=N`, where
//! `θ_k` is the material angle of edge `k` (the slot `θ_N` is unused and pinned). Every stencil
//! then couples indices within a band of half-width 10, and the Hessian is stored as a
//! [`BandedSym`].

pub(crate) mod bend_twist;
pub(crate) mod contact;
pub(crate) mod stretch;

use nalgebra::{Point3, Vector3};

use crate::banded::BandedSym;
use crate::dual::{Dual1, Dual2, Scalar, V3};
use crate::state::RodState;
use crate::world::World;

/// Half bandwidth of the Hessian.
pub(crate) const BANDWIDTH: usize = 10;

/// Index of coordinate `c` of node `k`.
#[inline]
pub(crate) fn x_dof(k: usize, c: usize) -> usize {
    4 * k + c
}

/// Index of the material angle of edge `j`.
#[inline]
pub(crate) fn theta_dof(j: usize) -> usize {
    4 * j + 3
}

/// Number of degrees of freedom for `n` edges.
pub(crate) fn dof_count(n: usize) -> usize {
    4 * (n + 1)
}

/// The energy of an equilibrium, split by kind \[J\].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energies {
    /// Stretching energy \[J\].
    pub stretch: f64,
    /// Bending energy \[J\].
    pub bend: f64,
    /// Twisting energy \[J\].
    pub twist: f64,
    /// Gravitational potential energy \[J\], zero at the world origin.
    pub gravity: f64,
    /// Contact penalty energy \[J\].
    pub contact: f64,
}

impl Energies {
    /// The total potential energy \[J\].
    pub fn total(&self) -> f64 {
        self.stretch + self.bend + self.twist + self.gravity + self.contact
    }
}

/// What to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    Energy,
    Gradient,
    Hessian,
}

/// Energy and derivatives over all degrees of freedom (fixed ones included).
pub(crate) struct Evaluation {
    pub energies: Energies,
    pub grad: Vec<f64>,
    pub hess: Option<BandedSym>,
    /// Force \[N\] each obstacle exerts on the wire, world frame.
    pub contact_forces: Vec<Vector3<f64>>,
}

fn dual_edge<const M: usize>(e: &Vector3<f64>, first: usize) -> V3<Dual2<M>> {
    [
        Dual2::var(e.x, first),
        Dual2::var(e.y, first + 1),
        Dual2::var(e.z, first + 2),
    ]
}

/// Maps the 8 local stencil variables `(e⁰, e¹, θ⁰, θ¹)` of vertex `i` to global DOFs with
/// coefficients (`e⁰ = x_i − x_{i−1}`, `e¹ = x_{i+1} − x_i`).
fn stencil_map(i: usize) -> [[(usize, f64); 2]; 8] {
    let mut map = [[(0, 0.0); 2]; 8];
    for c in 0..3 {
        map[c] = [(x_dof(i - 1, c), -1.0), (x_dof(i, c), 1.0)];
        map[3 + c] = [(x_dof(i, c), -1.0), (x_dof(i + 1, c), 1.0)];
    }
    map[6] = [(theta_dof(i - 1), 1.0), (theta_dof(i - 1), 0.0)];
    map[7] = [(theta_dof(i), 1.0), (theta_dof(i), 0.0)];
    map
}

/// Evaluates the total energy of `state` in `world`, with derivatives up to `order`.
///
/// The terms are assembled in a fixed order (stretching, bending and twisting, gravity,
/// contact), so that the gradient's sums, and the equilibria that depend on them, are
/// reproducible to the bit.
pub(crate) fn evaluate(world: &World, state: &RodState, order: Order) -> Evaluation {
    let ndof = dof_count(world.rod().edges());
    let mut sum = Assembly::new(ndof, order);
    sum.add_stretch(world, state);
    match order {
        Order::Energy => sum.add_bend_twist_energy(world, state),
        Order::Gradient => sum.add_bend_twist_gradient(world, state),
        Order::Hessian => sum.add_bend_twist_hessian(world, state),
    }
    sum.add_gravity(world, state);
    let contact_forces = sum.add_contact(world, state);
    Evaluation {
        energies: sum.energies,
        grad: sum.grad,
        hess: sum.hess,
        contact_forces,
    }
}

/// The bending–twisting constants of interior vertex `i`.
#[inline]
fn vertex_stencil<'a>(world: &'a World, state: &RodState, i: usize) -> bend_twist::Stencil<'a> {
    let rod = world.rod();
    let p = rod.params();
    bend_twist::Stencil {
        c: &p.stiffness,
        rest: &p.rest_strain,
        softening: p.bending_softening,
        voronoi: rod.edge_length(),
        ref_twist: state.ref_twist[i],
    }
}

/// The vector of edge `j`, `x_{j+1} − x_j` \[m\].
#[inline]
fn edge(state: &RodState, j: usize) -> Vector3<f64> {
    state.nodes[j + 1] - state.nodes[j]
}

/// The energy, gradient and Hessian of one [`evaluate`], summed term by term. The gradient is
/// empty for [`Order::Energy`], the Hessian present only for [`Order::Hessian`].
struct Assembly {
    order: Order,
    energies: Energies,
    grad: Vec<f64>,
    hess: Option<BandedSym>,
}

impl Assembly {
    fn new(ndof: usize, order: Order) -> Self {
        Self {
            order,
            energies: Energies::default(),
            grad: vec![0.0; if order == Order::Energy { 0 } else { ndof }],
            hess: (order == Order::Hessian).then(|| BandedSym::zeros(ndof, BANDWIDTH)),
        }
    }

    /// Adds the stretching energy of every edge, a function of its vector `e_j = x_{j+1} − x_j`.
    #[inline]
    fn add_stretch(&mut self, world: &World, state: &RodState) {
        let rod = world.rod();
        let n = rod.edges();
        let h = rod.edge_length();
        for j in 0..n {
            let e = edge(state, j);
            if self.order == Order::Energy {
                self.energies.stretch += stretch::energy(&e, h, rod.axial_stiffness());
                continue;
            }
            let (v, g, hs) = stretch::energy_derivatives(&e, h, rod.axial_stiffness());
            self.energies.stretch += v;
            for c in 0..3 {
                self.grad[x_dof(j, c)] -= g[c];
                self.grad[x_dof(j + 1, c)] += g[c];
            }
            if let Some(hm) = self.hess.as_mut() {
                add_pair_block(hm, j, j + 1, &hs, -1.0, 1.0);
            }
        }
    }

    /// Adds the bending and twisting energies at the interior vertices `1..N−1`, values only.
    /// Each edge's directors are computed once and shared by its two vertices.
    #[inline]
    fn add_bend_twist_energy(&mut self, world: &World, state: &RodState) {
        let n = world.rod().edges();
        let (rt, rd) = (&state.ref_tangent, &state.ref_d1);
        let dirs: Vec<bend_twist::Directors<f64>> = (0..n)
            .map(|j| bend_twist::directors(&edge(state, j).into(), &rt[j], &rd[j]))
            .collect();
        for i in 1..n {
            let dots = bend_twist::dots(&dirs[i - 1], &dirs[i]);
            let st = vertex_stencil(world, state, i);
            let (b, t) = bend_twist::energy(&dots, state.theta[i - 1], state.theta[i], &st);
            self.energies.bend += b;
            self.energies.twist += t;
        }
    }

    /// As [`Self::add_bend_twist_energy`], with the gradient: each edge's directors are
    /// differentiated in its own 3 variables, each vertex's energy in its 8 stencil variables
    /// ([`stencil_map`]).
    #[inline]
    fn add_bend_twist_gradient(&mut self, world: &World, state: &RodState) {
        let n = world.rod().edges();
        let (rt, rd) = (&state.ref_tangent, &state.ref_d1);
        let dirs: Vec<bend_twist::Directors<Dual1<3>>> = (0..n)
            .map(|j| {
                let e = edge(state, j);
                let ed = [Dual1::var(e.x, 0), Dual1::var(e.y, 1), Dual1::var(e.z, 2)];
                bend_twist::directors(&ed, &rt[j], &rd[j])
            })
            .collect();
        for i in 1..n {
            let dots = bend_twist::dots1(&dirs[i - 1], &dirs[i]);
            let (b, t) = bend_twist::energy(
                &dots,
                Dual1::var(state.theta[i - 1], 6),
                Dual1::var(state.theta[i], 7),
                &vertex_stencil(world, state, i),
            );
            self.energies.bend += b.re();
            self.energies.twist += t.re();
            let total = b + t;
            for (a, ma) in stencil_map(i).iter().enumerate() {
                for &(ga, ca) in ma {
                    self.grad[ga] += ca * total.g[a];
                }
            }
        }
    }

    /// As [`Self::add_bend_twist_gradient`], with the Hessian: the 8 × 8 stencil Hessian is
    /// scattered to the global degrees of freedom through [`stencil_map`].
    #[inline]
    fn add_bend_twist_hessian(&mut self, world: &World, state: &RodState) {
        let n = world.rod().edges();
        let (rt, rd) = (&state.ref_tangent, &state.ref_d1);
        let dirs: Vec<bend_twist::Directors<Dual2<3>>> = (0..n)
            .map(|j| bend_twist::directors(&dual_edge(&edge(state, j), 0), &rt[j], &rd[j]))
            .collect();
        for i in 1..n {
            let dots = bend_twist::dots2(&dirs[i - 1], &dirs[i]);
            let (b, t) = bend_twist::energy(
                &dots,
                Dual2::var(state.theta[i - 1], 6),
                Dual2::var(state.theta[i], 7),
                &vertex_stencil(world, state, i),
            );
            self.energies.bend += b.re();
            self.energies.twist += t.re();
            let total = b + t;
            let map = stencil_map(i);
            for (a, ma) in map.iter().enumerate() {
                for &(ga, ca) in ma {
                    self.grad[ga] += ca * total.g[a];
                }
            }
            if let Some(hm) = self.hess.as_mut() {
                add_stencil_hessian(hm, &map, &total);
            }
        }
    }

    /// Adds the gravitational energy of the lumped node masses, `−m_k·g·x_k`.
    #[inline]
    fn add_gravity(&mut self, world: &World, state: &RodState) {
        let rod = world.rod();
        let g = rod.params().gravity;
        for (k, x) in state.nodes.iter().enumerate() {
            let m = rod.node_mass(k);
            if m == 0.0 {
                continue;
            }
            self.energies.gravity -= m * g.dot(x);
            if self.order != Order::Energy {
                for c in 0..3 {
                    self.grad[x_dof(k, c)] -= m * g[c];
                }
            }
        }
    }

    /// Adds the contact penalty of every obstacle on the wire's samples (the clamped half
    /// edges excluded) and returns the force \[N\] each obstacle exerts on the wire, world
    /// frame (zero for [`Order::Energy`]).
    #[inline]
    fn add_contact(&mut self, world: &World, state: &RodState) -> Vec<Vector3<f64>> {
        let rod = world.rod();
        let n = rod.edges();
        let h = rod.edge_length();
        let nodes = &state.nodes;
        let mut contact_forces = vec![Vector3::zeros(); world.obstacles().len()];
        let radius = rod.params().radius;
        let stiffness = world.contact_stiffness();
        let count = world.samples_per_edge();
        for (o, obstacle) in world.obstacles().iter().enumerate() {
            for j in 0..n {
                let (lo, hi) = if j == 0 {
                    (0.5, 1.0)
                } else if j == n - 1 {
                    (0.0, 0.5)
                } else {
                    (0.0, 1.0)
                };
                let (xa, xb) = (nodes[j], nodes[j + 1]);
                // Cheap rejection: the edge's bounding sphere is clear of the obstacle.
                let mid = Point3::from((xa + xb) * 0.5);
                let reach = 0.5 * (xb - xa).norm() + radius;
                if obstacle.distance_derivatives(&mid).0 > reach {
                    continue;
                }
                for (s, w) in contact::samples(lo, hi, count, h) {
                    let pt = Point3::from(xa * (1.0 - s) + xb * s);
                    let Some((v, gp, hp)) = contact::sample_penalty(
                        obstacle,
                        &pt,
                        radius,
                        stiffness,
                        w,
                        self.order == Order::Hessian,
                    ) else {
                        continue;
                    };
                    self.energies.contact += v;
                    if self.order == Order::Energy {
                        continue;
                    }
                    contact_forces[o] -= gp;
                    for c in 0..3 {
                        self.grad[x_dof(j, c)] += (1.0 - s) * gp[c];
                        self.grad[x_dof(j + 1, c)] += s * gp[c];
                    }
                    if let Some(hm) = self.hess.as_mut() {
                        add_pair_block(hm, j, j + 1, &hp, 1.0 - s, s);
                    }
                }
            }
        }
        contact_forces
    }
}

/// Adds `Mᵀ·H·M` for the stencil map `M` of one vertex ([`stencil_map`]) and the 8 × 8 Hessian
/// `H` of its energy in the stencil variables, lower triangle only.
#[inline]
fn add_stencil_hessian(hm: &mut BandedSym, map: &[[(usize, f64); 2]; 8], total: &Dual2<8>) {
    for (a, ma) in map.iter().enumerate() {
        for (b2, mb) in map.iter().enumerate() {
            let v = total.hess(a, b2);
            for &(ga, ca) in ma {
                for &(gb, cb) in mb {
                    if ga >= gb && ca != 0.0 && cb != 0.0 {
                        hm.add_lower(ga, gb, ca * cb * v);
                    }
                }
            }
        }
    }
}

/// Adds `Aᵀ·H·A` for `p = ca·x_a + cb·x_b` (`a < b`, `H` the 3 × 3 Hessian in `p`).
fn add_pair_block(
    hm: &mut BandedSym,
    a: usize,
    b: usize,
    h: &nalgebra::Matrix3<f64>,
    ca: f64,
    cb: f64,
) {
    for r in 0..3 {
        for c in 0..3 {
            let v = h[(r, c)];
            if r >= c {
                hm.add_lower(x_dof(a, r), x_dof(a, c), ca * ca * v);
                hm.add_lower(x_dof(b, r), x_dof(b, c), cb * cb * v);
            }
            // Block (b, a): rows of b, columns of a (b > a so always lower).
            hm.add_lower(x_dof(b, r), x_dof(a, c), cb * ca * v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete_rod::RodParams;
    use crate::obstacle::{BoxObstacle, Floor};
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    /// A small deterministic generator (xorshift64*), uniform in [−1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            v as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A random, curved and twisted state with random reference frames.
    fn random_state(world: &World, rng: &mut Rng) -> RodState {
        let rod = world.rod();
        let n = rod.edges();
        let h = rod.edge_length();
        let mut s = RodState::straight(rod, &Isometry3::identity());
        // A helix-like curve plus noise.
        let mut dir = Vector3::x();
        let mut x = Vector3::new(-0.5 * h, 0.0, 0.0);
        for k in 0..=n {
            s.nodes[k] = x;
            let turn = Vector3::new(rng.next(), rng.next(), rng.next()) * 0.4;
            dir = (UnitQuaternion::from_scaled_axis(turn) * dir).normalize();
            x += dir * h * (1.0 + 0.01 * rng.next());
        }
        for j in 0..n {
            let t = (s.nodes[j + 1] - s.nodes[j]).normalize();
            // Reference stored at a nearby tangent, so time-parallel transport is exercised.
            let t_ref = (t + Vector3::new(rng.next(), rng.next(), rng.next()) * 0.2).normalize();
            s.ref_tangent[j] = t_ref;
            s.ref_d1[j] = crate::transport::perpendicular(
                &t_ref,
                &Vector3::new(rng.next(), rng.next(), rng.next()),
            );
            s.theta[j] = 2.0 * rng.next();
        }
        s
    }

    fn perturbed(s: &RodState, i: usize, d: f64) -> RodState {
        let mut t = s.clone();
        if i % 4 == 3 {
            t.theta[i / 4] += d;
        } else {
            t.nodes[i / 4][i % 4] += d;
        }
        t
    }

    fn check_world(world: &World, seed: u64) {
        let mut rng = Rng(seed);
        let state = random_state(world, &mut rng);
        let n = world.rod().edges();
        let ev = evaluate(world, &state, Order::Hessian);
        let hess = ev.hess.as_ref().expect("hessian");
        // The gradient-only path agrees with the Hessian path.
        let ev1 = evaluate(world, &state, Order::Gradient);
        for (a, b) in ev1.grad.iter().zip(&ev.grad) {
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
        }
        let ndof = dof_count(n);
        let h = world.rod().edge_length();
        let mut worst_g: f64 = 0.0;
        let mut worst_h: f64 = 0.0;
        let gscale = ev.grad.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut hscale: f64 = 0.0;
        for i in 0..ndof {
            hscale = hscale.max(hess.get(i, i).abs());
        }
        for i in 0..ndof - 1 {
            let d = if i % 4 == 3 { 1e-6 } else { 1e-6 * h };
            let ep = evaluate(world, &perturbed(&state, i, d), Order::Hessian);
            let em = evaluate(world, &perturbed(&state, i, -d), Order::Hessian);
            let fd = (ep.energies.total() - em.energies.total()) / (2.0 * d);
            worst_g = worst_g.max((fd - ev.grad[i]).abs() / gscale);
            for j in 0..ndof {
                let fd_h = (ep.grad[j] - em.grad[j]) / (2.0 * d);
                let dj = if j % 4 == 3 { 1.0 } else { h };
                let di = if i % 4 == 3 { 1.0 } else { h };
                // Compare in units where both variables are O(1).
                let err = (fd_h - hess.get(i, j)).abs() * di * dj;
                worst_h = worst_h.max(err / (hscale * h * h));
            }
        }
        assert!(worst_g < 1e-6, "seed {seed}: gradient error {worst_g:e}");
        assert!(worst_h < 1e-6, "seed {seed}: Hessian error {worst_h:e}");
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        let params = RodParams {
            stiffness: [0.03, 0.05, 0.08],
            rest_strain: Vector3::new(0.7, -1.5, 2.5),
            axial_stiffness: Some(50.0),
            ..RodParams::default().with_edges(7)
        };
        let world = World::new(params).expect("valid");
        for seed in 1..=6 {
            check_world(&world, seed);
        }
    }

    #[test]
    fn softened_bending_derivatives_match_finite_differences() {
        let params = RodParams {
            stiffness: [0.03, 0.05, 0.08],
            rest_strain: Vector3::new(0.7, -1.5, 2.5),
            axial_stiffness: Some(50.0),
            bending_softening: Some(2.0),
            ..RodParams::default().with_edges(7)
        };
        let world = World::new(params).expect("valid");
        for seed in 21..=26 {
            let state = random_state(&world, &mut Rng(seed));
            let linear = World::new(RodParams {
                bending_softening: None,
                ..params
            })
            .expect("valid");
            let soft = evaluate(&world, &state, Order::Energy).energies.bend;
            let hard = evaluate(&linear, &state, Order::Energy).energies.bend;
            assert!(
                soft < 0.95 * hard,
                "seed {seed}: {soft} vs {hard}: must soften"
            );
            check_world(&world, seed);
        }
    }

    #[test]
    fn contact_derivatives_match_finite_differences() {
        let params = RodParams {
            length: 0.06,
            axial_stiffness: Some(50.0),
            ..RodParams::default().with_edges(7)
        };
        let obstacle = BoxObstacle::new(
            Isometry3::from_parts(
                Translation3::new(0.02, 0.004, 0.0),
                UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.2, 0.1)),
            ),
            Vector3::new(0.006, 0.004, 0.01),
        )
        .expect("valid");
        let world = World::new(params)
            .expect("valid")
            .with_box(obstacle)
            .with_floor(Floor { height: 0.0 })
            .expect("valid")
            .with_contact_stiffness(1e6)
            .expect("valid");
        for seed in 11..=14 {
            let mut rng = Rng(seed);
            let state = random_state(&world, &mut rng);
            let ev = evaluate(&world, &state, Order::Gradient);
            assert!(
                ev.energies.contact > 0.0,
                "seed {seed}: the test must touch"
            );
            check_world(&world, seed);
        }
    }
}

#[cfg(test)]
mod timing {
    use super::*;
    use crate::discrete_rod::RodParams;

    #[test]
    #[ignore = "timing probe, run by hand in release"]
    fn hessian_evaluation_time() {
        let world = World::new(RodParams::default()).expect("valid");
        let tip = nalgebra::Isometry3::translation(0.4, 0.2, 0.0);
        let eq = world
            .solve_cold(&nalgebra::Isometry3::identity(), &tip)
            .expect("solves")
            .equilibrium;
        let t = std::time::Instant::now();
        for _ in 0..100 {
            std::hint::black_box(evaluate(&world, &eq.state, Order::Hessian));
        }
        let th = t.elapsed().as_secs_f64() / 100.0;
        let t = std::time::Instant::now();
        for _ in 0..100 {
            std::hint::black_box(evaluate(&world, &eq.state, Order::Energy));
        }
        let te = t.elapsed().as_secs_f64() / 100.0;
        let h = evaluate(&world, &eq.state, Order::Hessian).hess.expect("h");
        let t = std::time::Instant::now();
        for _ in 0..100 {
            std::hint::black_box(h.cholesky());
        }
        let tc = t.elapsed().as_secs_f64() / 100.0;
        println!(
            "hessian {:.1} µs, energy {:.1} µs, cholesky {:.1} µs",
            th * 1e6,
            te * 1e6,
            tc * 1e6
        );
    }
}
