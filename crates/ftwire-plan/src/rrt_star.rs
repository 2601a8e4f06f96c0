//! RRT* (Karaman & Frazzoli 2011) in a [`Space`]: the paper's planner in `A_free` (§III-D) and
//! the same algorithm in `Z = A × Q` (Sintov et al. 2020).
//!
//! - **Sampling:** uniform in the space's box, with probability [`PlannerParams::goal_bias`]
//!   the goal; once a path exists, informed (Gammell et al. 2014): uniform in the prolate
//!   hyperspheroid of states that could shorten it.
//! - **Extension:** the new state lies at most [`PlannerParams::step`] from the node nearest
//!   the sample, and the edge from that node gates the iteration (Karaman & Frazzoli 2011,
//!   Alg. 6 line 5, `ObstacleFree(x_nearest, x_new)`): only a state that node reaches is
//!   added, so a failed iteration costs one edge check.
//! - **Neighbours:** a kd-tree ([`kiddo`]); the `k = ⌈k_rrt · ln n⌉` nearest
//!   (`k_rrt = 2e`, the k-nearest RRT* constant) are candidate parents, up to
//!   [`PlannerParams::parent_attempts`] of them cheaper than the nearest node tried in order of
//!   cost, and are rewired.
//! - **Edges** are checked by [`Checker::edge`] at the resolution its module documents; a
//!   rewired node keeps its joints only if the new edge arrives within
//!   [`ValidityParams::max_joint_step`](crate::ValidityParams::max_joint_step) of them. An
//!   extension found invalid is remembered by its start node and end state, and not checked
//!   again: goal-biased samples repeat the same extension until the tree grows near it. The
//!   check is deterministic, so this changes the time and not the path.
//! - **Cost:** an edge of length `ℓ` whose smallest clearance is `c` costs
//!   `ℓ · (1 + w · max(0, c_ref / c − 1))` ([`PlannerParams::clearance_weight`] `w`,
//!   [`PlannerParams::clearance_reference`] `c_ref`): the length alone when `w = 0`, and a
//!   penalty on edges that pass closer than `c_ref` to an obstacle otherwise.
//! - **Anytime:** the loop runs until [`PlannerParams::time_budget`] or
//!   [`PlannerParams::max_iterations`] (or the first path, [`PlannerParams::stop_at_first`]),
//!   and returns the best path so far, shortcut by [`PlannerParams::shortcut_attempts`] random
//!   straight connections.
//! - **Seeded:** every random choice comes from one ChaCha8 stream seeded by
//!   [`PlannerParams::seed`]; with an iteration budget (no time budget) the same seed gives the
//!   same path (test `same_seed_same_path`). With a time budget the iteration count depends on
//!   the machine; [`Plan::iterations`] says how many ran, to replay with `max_iterations`.

use std::collections::HashSet;
use std::time::{Duration, Instant};

use kiddo::{KdTree, SquaredEuclidean};
use nalgebra::{SMatrix, SVector};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::validity::{Checker, Edge, Sample, joint_distance};
use crate::{Path, PlanError, Space, ZPoint};

/// Settings of [`plan`] (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannerParams {
    /// Seed of the planner's random stream (default `0`).
    pub seed: u64,
    /// Wall-clock budget (default: none; then `max_iterations` bounds the run).
    pub time_budget: Option<Duration>,
    /// Most iterations (default `2000`).
    pub max_iterations: usize,
    /// Stop at the first path found (default `false`).
    pub stop_at_first: bool,
    /// Probability of sampling the goal (default `0.2`).
    pub goal_bias: f64,
    /// Longest extension toward a sample, in the space's metric (default `1.5`).
    pub step: f64,
    /// A new node within this distance of the goal tries to connect to it (default `5.0`; a
    /// long connection costs one edge check, a missed one many iterations).
    pub goal_radius: f64,
    /// Candidate parents cheaper than the nearest node whose edges are checked, cheapest first,
    /// once the nearest node's edge is valid (default `4`).
    pub parent_attempts: usize,
    /// Weight `w` of the clearance penalty (default `0`: cost = length).
    pub clearance_weight: f64,
    /// Clearance \[m\] below which an edge is penalised (default `0.02`).
    pub clearance_reference: f64,
    /// Random shortcut attempts on the best path at the end (default `50`).
    pub shortcut_attempts: usize,
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            seed: 0,
            time_budget: None,
            max_iterations: 2000,
            stop_at_first: false,
            goal_bias: 0.2,
            step: 1.5,
            goal_radius: 5.0,
            parent_attempts: 4,
            clearance_weight: 0.0,
            clearance_reference: 0.02,
            shortcut_attempts: 50,
        }
    }
}

/// The outcome of [`plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The best path found, shortcut.
    pub path: Path,
    /// Iterations run.
    pub iterations: usize,
    /// Nodes in the tree at the end.
    pub nodes: usize,
    /// The iteration that found the first path.
    pub first_path_iteration: usize,
    /// Wall time to the first path \[s\].
    pub first_path_seconds: f64,
    /// Cost of the first path found (before shortcutting).
    pub first_path_cost: f64,
    /// Cost of the best path before shortcutting.
    pub best_cost_before_shortcut: f64,
    /// Wall time of the whole run \[s\].
    pub seconds: f64,
}

struct Node<const D: usize> {
    x: SVector<f64, D>,
    parent: Option<usize>,
    cost: f64,
    /// The edge from the parent.
    edge: Link,
    sample: Sample,
    children: Vec<usize>,
}

/// An edge's cost and its smallest clearance \[m\].
#[derive(Debug, Clone, Copy)]
struct Link {
    cost: f64,
    clearance: f64,
}

impl Link {
    /// The cost of an edge of `length` whose smallest clearance is `clearance` (module docs).
    fn new(params: &PlannerParams, length: f64, clearance: f64) -> Self {
        let penalty = (params.clearance_reference / clearance.max(1e-6) - 1.0).max(0.0);
        Self {
            cost: length * (1.0 + params.clearance_weight * penalty),
            clearance,
        }
    }
}

fn check_params(params: &PlannerParams) -> Result<(), PlanError> {
    PlanError::check_positive(&[
        ("step", params.step),
        ("goal_radius", params.goal_radius),
        ("clearance_reference", params.clearance_reference),
    ])?;
    if !(0.0..=1.0).contains(&params.goal_bias) {
        return Err(PlanError::InvalidParameter {
            name: "goal_bias",
            value: params.goal_bias,
            allowed: "a probability in [0, 1]",
        });
    }
    if !(params.clearance_weight.is_finite() && params.clearance_weight >= 0.0) {
        return Err(PlanError::InvalidParameter {
            name: "clearance_weight",
            value: params.clearance_weight,
            allowed: "a finite value >= 0",
        });
    }
    Ok(())
}

/// A standard normal draw (Box–Muller), so that no distribution crate is needed.
fn normal<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    let u: f64 = 1.0 - rng.random::<f64>();
    let v: f64 = rng.random::<f64>();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Informed sampling: a uniform point of the prolate hyperspheroid with foci `start`, `goal`
/// and transverse diameter `c_best`, clipped to the box (rejection, else uniform in the box).
struct Informed<const D: usize> {
    centre: SVector<f64, D>,
    rotation: SMatrix<f64, D, D>,
    c_min: f64,
}

impl<const D: usize> Informed<D> {
    fn new(start: &SVector<f64, D>, goal: &SVector<f64, D>) -> Self {
        let d = goal - start;
        let c_min = d.norm();
        // A Householder reflection taking e1 to the start→goal direction.
        let mut rotation = SMatrix::<f64, D, D>::identity();
        if c_min > 0.0 {
            let u = d / c_min;
            let mut v = -u;
            v[0] += 1.0;
            let vv = v.dot(&v);
            if vv > 1e-24 {
                rotation -= (v * v.transpose()) * (2.0 / vv);
            }
        }
        Self {
            centre: 0.5 * (start + goal),
            rotation,
            c_min,
        }
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R, c_best: f64) -> SVector<f64, D> {
        let mut ball = SVector::<f64, D>::from_fn(|_, _| normal(rng));
        let norm = ball.norm().max(1e-300);
        let r = rng.random::<f64>().powf(1.0 / D as f64);
        ball *= r / norm;
        let long = 0.5 * c_best;
        let short = 0.5 * (c_best * c_best - self.c_min * self.c_min).max(0.0).sqrt();
        for i in 0..D {
            ball[i] *= if i == 0 { long } else { short };
        }
        self.centre + self.rotation * ball
    }
}

fn uniform<R: Rng + ?Sized, const D: usize>(
    rng: &mut R,
    lo: &SVector<f64, D>,
    hi: &SVector<f64, D>,
) -> SVector<f64, D> {
    SVector::from_fn(|i, _| lo[i] + (hi[i] - lo[i]) * rng.random::<f64>())
}

fn key<const D: usize>(x: &SVector<f64, D>) -> [f64; D] {
    std::array::from_fn(|i| x[i])
}

fn joints_close(checker: &Checker, a: &Sample, b: &Sample) -> bool {
    joint_distance(&a.joints, &b.joints) <= checker.params().max_joint_step
}

/// The extensions found invalid, by their start node and end state: a goal-biased sample
/// repeats the same extension from the same nearest node until the tree changes near it, and
/// an edge's check is deterministic, so a repeat is answered from here.
#[derive(Default)]
struct FailedEdges<const D: usize> {
    edges: HashSet<(usize, [u64; D])>,
}

impl<const D: usize> FailedEdges<D> {
    /// [`Checker::edge`] from node `from` (its sample `sample`) to the state `x` (`config`),
    /// or `None` if that edge is, or was found, invalid.
    fn check(
        &mut self,
        checker: &Checker,
        from: usize,
        sample: &Sample,
        x: &SVector<f64, D>,
        config: &ZPoint,
    ) -> Option<Edge> {
        let id = (from, std::array::from_fn(|i| x[i].to_bits()));
        if self.edges.contains(&id) {
            return None;
        }
        let edge = checker.edge(sample, config).ok();
        if edge.is_none() {
            self.edges.insert(id);
        }
        edge
    }
}

/// Appends a node under `parent`, reached by `edge`; returns its index.
fn add_node<const D: usize>(
    nodes: &mut Vec<Node<D>>,
    x: SVector<f64, D>,
    parent: usize,
    edge: Link,
    sample: Sample,
) -> usize {
    let id = nodes.len();
    let cost = nodes[parent].cost + edge.cost;
    nodes.push(Node {
        x,
        parent: Some(parent),
        cost,
        edge,
        sample,
        children: Vec::new(),
    });
    nodes[parent].children.push(id);
    id
}

/// Plans from a valid `start` sample to the `goal` configuration with RRT* in `space`.
///
/// Each iteration samples a state, extends the tree toward it, rewires the neighbours through
/// the new node and tries to connect it to the goal (module docs); at the end the best path is
/// shortcut.
///
/// # Errors
/// [`PlanError::InvalidParameter`] for a bad setting; [`PlanError::NoPath`] when the budget
/// ends without a path.
pub fn plan<const D: usize, S: Space<D>>(
    space: &S,
    checker: &Checker,
    start: &Sample,
    goal: &ZPoint,
    params: &PlannerParams,
) -> Result<Plan, PlanError> {
    check_params(params)?;
    let clock = Instant::now();
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let mut search = Search::new(space, checker, start, goal, params);
    let mut first: Option<(usize, f64, f64)> = None;
    let mut iterations = 0;

    let out_of_time = |clock: &Instant| params.time_budget.is_some_and(|b| clock.elapsed() >= b);
    while iterations < params.max_iterations && !out_of_time(&clock) {
        iterations += 1;
        let best = search.best_cost();
        let x_rand = search.sample(&mut rng, best);
        let Some(extension) = search.extend(&x_rand, best) else {
            continue;
        };
        search.rewire(&extension);
        if let Some(g) = search.connect_goal(extension.id)
            && first.is_none()
        {
            first = Some((
                iterations,
                clock.elapsed().as_secs_f64(),
                search.nodes[g].cost,
            ));
            if params.stop_at_first {
                break;
            }
        }
    }

    let Some(best_goal) = search.best_goal() else {
        return Err(PlanError::NoPath {
            iterations,
            nodes: search.nodes.len(),
            seconds: clock.elapsed().as_secs_f64(),
        });
    };
    let best_cost = search.nodes[best_goal].cost;
    let mut chain = search.chain_to(best_goal);
    shortcut(space, checker, params, &mut rng, &mut chain);
    let (first_iteration, first_seconds, first_cost) =
        first.unwrap_or((iterations, 0.0, best_cost));
    Ok(Plan {
        path: Path {
            cost: chain.iter().map(|c| c.2.cost).sum(),
            edge_clearance: chain.iter().skip(1).map(|c| c.2.clearance).collect(),
            waypoints: chain.into_iter().map(|c| c.1).collect(),
        },
        iterations,
        nodes: search.nodes.len(),
        first_path_iteration: first_iteration,
        first_path_seconds: first_seconds,
        first_path_cost: first_cost,
        best_cost_before_shortcut: best_cost,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// A node just added to the tree, with its parent and the candidate parents found for it
/// (index and distance, cheapest cost-to-come first), which are its neighbours to rewire.
struct Extension {
    id: usize,
    parent: usize,
    near: Vec<(usize, f64)>,
}

/// The state of one RRT* run: the tree (nodes and their kd-tree), the goal nodes reached and
/// the extensions found invalid.
struct Search<'a, const D: usize, S: Space<D>> {
    space: &'a S,
    checker: &'a Checker,
    params: &'a PlannerParams,
    goal: &'a ZPoint,
    x_goal: SVector<f64, D>,
    lo: SVector<f64, D>,
    hi: SVector<f64, D>,
    informed: Informed<D>,
    nodes: Vec<Node<D>>,
    tree: KdTree<f64, D>,
    /// Nodes at the goal state, each the end of a path.
    goals: Vec<usize>,
    failed: FailedEdges<D>,
}

impl<'a, const D: usize, S: Space<D>> Search<'a, D, S> {
    /// A tree holding only the start.
    fn new(
        space: &'a S,
        checker: &'a Checker,
        start: &Sample,
        goal: &'a ZPoint,
        params: &'a PlannerParams,
    ) -> Self {
        let (lo, hi) = (space.lower(), space.upper());
        let x_start = space.state(&start.config);
        let x_goal = space.state(goal);
        let informed = Informed::new(&x_start, &x_goal);
        let nodes: Vec<Node<D>> = vec![Node {
            x: x_start,
            parent: None,
            cost: 0.0,
            edge: Link {
                cost: 0.0,
                clearance: start.clearance,
            },
            sample: start.clone(),
            children: Vec::new(),
        }];
        let mut tree: KdTree<f64, D> = KdTree::new();
        tree.add(&key(&x_start), 0);
        Self {
            space,
            checker,
            params,
            goal,
            x_goal,
            lo,
            hi,
            informed,
            nodes,
            tree,
            goals: Vec::new(),
            failed: FailedEdges::default(),
        }
    }

    /// The cost of the best path so far (infinite before the first).
    fn best_cost(&self) -> f64 {
        self.goals
            .iter()
            .map(|&g| self.nodes[g].cost)
            .fold(f64::INFINITY, f64::min)
    }

    /// The goal node of the cheapest path, if any.
    fn best_goal(&self) -> Option<usize> {
        self.goals
            .iter()
            .min_by(|&&a, &&b| self.nodes[a].cost.total_cmp(&self.nodes[b].cost))
            .copied()
    }

    /// The state to extend toward: the goal with probability [`PlannerParams::goal_bias`],
    /// else uniform in the box before the first path and informed after it (up to 100
    /// rejections of points outside the box, then the uniform draw made first).
    fn sample(&self, rng: &mut ChaCha8Rng, best: f64) -> SVector<f64, D> {
        if rng.random::<f64>() < self.params.goal_bias {
            self.x_goal
        } else if best.is_finite() {
            let mut x = uniform(rng, &self.lo, &self.hi);
            for _ in 0..100 {
                let y = self.informed.sample(rng, best);
                if (0..D).all(|i| y[i] >= self.lo[i] && y[i] <= self.hi[i]) {
                    x = y;
                    break;
                }
            }
            x
        } else {
            uniform(rng, &self.lo, &self.hi)
        }
    }

    /// Adds a node toward `x_rand`: at most [`PlannerParams::step`] from the nearest node, with
    /// the cheapest parent whose edge is valid. `None` when `x_rand` is a node, the new state
    /// is already in the tree, no parent could bring it under the `best` path's cost, or the
    /// nearest node's edge to it is invalid (module docs: the extension gates the iteration).
    fn extend(&mut self, x_rand: &SVector<f64, D>, best: f64) -> Option<Extension> {
        let nearest = self.tree.nearest_one::<SquaredEuclidean>(&key(x_rand)).item as usize;
        let d = x_rand - self.nodes[nearest].x;
        let dist = d.norm();
        let x_new = if dist > self.params.step {
            self.nodes[nearest].x + d * (self.params.step / dist)
        } else {
            *x_rand
        };
        if dist == 0.0 {
            return None;
        }
        let config = self.space.config(&x_new);
        let near = self.near_by_cost(&x_new)?;
        // Informed pruning: no parent could bring the new state under the best path's cost.
        if near
            .first()
            .is_none_or(|&(i, d)| self.nodes[i].cost + d >= best)
        {
            return None;
        }
        let step_length = dist.min(self.params.step);
        let (parent, link, sample) =
            self.choose_parent(nearest, step_length, &near, &x_new, &config)?;
        if self.nodes[parent].cost + link.cost >= best {
            return None;
        }
        let id = add_node(&mut self.nodes, x_new, parent, link, sample);
        self.tree.add(&key(&x_new), id as u64);
        Some(Extension { id, parent, near })
    }

    /// The candidate parents of `x_new`: the `k = ⌈2e · ln(n + 1)⌉` nearest nodes with their
    /// distances, sorted by cost-to-come plus distance. `None` if `x_new` is already in the
    /// tree (kiddo's buckets cannot split more than their size of identical points).
    fn near_by_cost(&self, x_new: &SVector<f64, D>) -> Option<Vec<(usize, f64)>> {
        let n = self.nodes.len();
        let k = ((2.0 * std::f64::consts::E * (n as f64 + 1.0).ln()).ceil() as usize).clamp(1, n);
        let mut near: Vec<(usize, f64)> = self
            .tree
            .nearest_n::<SquaredEuclidean>(&key(x_new), k)
            .into_iter()
            .map(|nb| (nb.item as usize, nb.distance.sqrt()))
            .collect();
        if near.iter().any(|&(_, d)| d < 1e-12) {
            return None;
        }
        let nodes = &self.nodes;
        near.sort_by(|a, b| {
            (nodes[a.0].cost + a.1)
                .total_cmp(&(nodes[b.0].cost + b.1))
                .then(a.0.cmp(&b.0))
        });
        Some(near)
    }

    /// The parent of `x_new`, the edge's cost and the sample it arrives at: the nearest node's
    /// edge is checked first (`None` if invalid, Karaman & Frazzoli 2011, Alg. 6 line 5), then
    /// up to [`PlannerParams::parent_attempts`] cheaper candidates in order of cost, the first
    /// valid one taken.
    fn choose_parent(
        &mut self,
        nearest: usize,
        step_length: f64,
        near: &[(usize, f64)],
        x_new: &SVector<f64, D>,
        config: &ZPoint,
    ) -> Option<(usize, Link, Sample)> {
        let params = self.params;
        let nodes = &self.nodes;
        let edge =
            self.failed
                .check(self.checker, nearest, &nodes[nearest].sample, x_new, config)?;
        let mut chosen = (
            nearest,
            Link::new(params, step_length, edge.min_clearance),
            edge.end,
        );
        for &(i, d) in near.iter().take(params.parent_attempts) {
            if i == nearest || nodes[i].cost + d >= nodes[nearest].cost + chosen.1.cost {
                break;
            }
            if let Some(edge) = self
                .failed
                .check(self.checker, i, &nodes[i].sample, x_new, config)
            {
                chosen = (i, Link::new(params, d, edge.min_clearance), edge.end);
                break;
            }
        }
        Some(chosen)
    }

    /// Rewires the neighbours of the new node through it where that is cheaper and the edge
    /// arrives at the neighbour's joints.
    fn rewire(&mut self, extension: &Extension) {
        let id = extension.id;
        for &(i, d) in &extension.near {
            if i == extension.parent || self.nodes[id].cost + d >= self.nodes[i].cost {
                continue;
            }
            let target = self.space.config(&self.nodes[i].x);
            let Ok(edge) = self.checker.edge(&self.nodes[id].sample, &target) else {
                continue;
            };
            let c = Link::new(self.params, d, edge.min_clearance);
            if self.nodes[id].cost + c.cost < self.nodes[i].cost
                && joints_close(self.checker, &edge.end, &self.nodes[i].sample)
            {
                reparent(&mut self.nodes, i, id, c);
            }
        }
    }

    /// Connects node `id` to the goal if it lies within [`PlannerParams::goal_radius`] and the
    /// edge is valid; returns the new goal node.
    fn connect_goal(&mut self, id: usize) -> Option<usize> {
        let x_new = self.nodes[id].x;
        let within = (self.x_goal - x_new).norm() <= self.params.goal_radius;
        if !within {
            return None;
        }
        let edge = self.checker.edge(&self.nodes[id].sample, self.goal).ok()?;
        let d = (self.x_goal - x_new).norm();
        let c = Link::new(self.params, d, edge.min_clearance);
        let g = add_node(&mut self.nodes, self.x_goal, id, c, edge.end);
        self.goals.push(g);
        Some(g)
    }

    /// The path from the start to node `end`: each node's state, sample and incoming edge.
    fn chain_to(&self, end: usize) -> Vec<(SVector<f64, D>, Sample, Link)> {
        let mut chain = Vec::new();
        let mut at = Some(end);
        while let Some(i) = at {
            chain.push((
                self.nodes[i].x,
                self.nodes[i].sample.clone(),
                self.nodes[i].edge,
            ));
            at = self.nodes[i].parent;
        }
        chain.reverse();
        chain
    }
}

/// Moves node `i` under `parent` by edge `c`, and updates the costs of its subtree.
fn reparent<const D: usize>(nodes: &mut [Node<D>], i: usize, parent: usize, c: Link) {
    if let Some(old) = nodes[i].parent {
        nodes[old].children.retain(|&ch| ch != i);
    }
    nodes[i].parent = Some(parent);
    nodes[parent].children.push(i);
    let delta = nodes[parent].cost + c.cost - nodes[i].cost;
    nodes[i].edge = c;
    let mut stack = vec![i];
    while let Some(j) = stack.pop() {
        nodes[j].cost += delta;
        stack.extend(nodes[j].children.iter().copied());
    }
}

/// Random shortcuts: replace the waypoints between `i` and `j` by the straight edge when it is
/// valid, cheaper, and arrives at `j` with its joints.
fn shortcut<const D: usize, S: Space<D>, R: Rng + ?Sized>(
    space: &S,
    checker: &Checker,
    params: &PlannerParams,
    rng: &mut R,
    chain: &mut Vec<(SVector<f64, D>, Sample, Link)>,
) {
    for _ in 0..params.shortcut_attempts {
        if chain.len() < 3 {
            return;
        }
        let i = rng.random_range(0..chain.len() - 2);
        let j = rng.random_range(i + 2..chain.len());
        let old: f64 = chain[i + 1..=j].iter().map(|c| c.2.cost).sum();
        let d = (chain[j].0 - chain[i].0).norm();
        if d >= old {
            continue;
        }
        let Ok(edge) = checker.edge(&chain[i].1, &space.config(&chain[j].0)) else {
            continue;
        };
        let c = Link::new(params, d, edge.min_clearance);
        if c.cost < old && joints_close(checker, &edge.end, &chain[j].1) {
            chain[j].2 = c;
            chain.drain(i + 1..j);
        }
    }
}
