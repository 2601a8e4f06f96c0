//! A planning scene's obstacles for the simulator: the planner (`ftwire-plan`) and the
//! ground truth (`ftwire-sim`) read the same scene file, and this is the one place that turns
//! it into the simulator's [`Obstacle`]s (only the binary sees both sides of the wall).
//!
//! Frames: the scene's poses are in the robot's world frame, the frame of the rig's gripper
//! poses, which is the simulator's world frame.

use ftwire_plan::{Scene, SceneBox};

/// The shipped passage scene (`scenes/passage.toml`, paper §IV-E), built into the binary.
pub const PASSAGE: &str = include_str!("../../../scenes/passage.toml");
use ftwire_sim::{BoxObstacle, Floor, Obstacle, SimError, World};

/// The scene's boxes (in file order) and its floor (last, if any) as simulator obstacles.
///
/// # Errors
/// [`SimError`] if the simulator refuses a box (it cannot for a parsed scene, whose half
/// extents are positive and poses finite).
///
/// # Example
/// ```
/// let text = "[base]\nposition = [0.6, 0.35, 0.35]\n[floor]\nheight = -0.2\n\
///     [[obstacle]]\ncentre = [0.8, 0.0, 0.3]\nhalf_extents = [0.1, 0.02, 0.1]\n";
/// let scene = ftwire_plan::Scene::from_toml(text, "demo")?;
/// let obstacles = ftwire_lab::scene::sim_obstacles(&scene)?;
/// assert_eq!(obstacles.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sim_obstacles(scene: &Scene) -> Result<Vec<Obstacle>, SimError> {
    let mut out = scene
        .boxes
        .iter()
        .map(|b| {
            BoxObstacle::new(*b.geometry.pose(), *b.geometry.half_extents()).map(Obstacle::Box)
        })
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(height) = scene.floor {
        out.push(Obstacle::Floor(Floor { height }));
    }
    Ok(out)
}

/// `world` with the scene's obstacles added.
///
/// # Errors
/// As [`sim_obstacles`], or [`World::with_floor`].
pub fn with_scene(world: World, scene: &Scene) -> Result<World, SimError> {
    let mut world = world;
    for obstacle in sim_obstacles(scene)? {
        world = match obstacle {
            Obstacle::Box(b) => world.with_box(b),
            Obstacle::Floor(f) => world.with_floor(f)?,
        };
    }
    Ok(world)
}

/// A box's outline for figures: its eight corners as one polyline over its twelve edges (the
/// two faces' loops, then the four edges between them), world frame \[m\].
pub fn box_outline(b: &SceneBox) -> Vec<[f64; 3]> {
    let pose = b.geometry.pose();
    let h = b.geometry.half_extents();
    let corner = |i: usize| {
        let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
        let p = pose * nalgebra::Point3::new(sign(1) * h.x, sign(2) * h.y, sign(4) * h.z);
        [p.x, p.y, p.z]
    };
    [0, 1, 3, 2, 0, 4, 5, 7, 6, 4, 5, 1, 3, 7, 6, 2]
        .iter()
        .map(|&i| corner(i))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_outline_visits_every_corner_and_stays_on_the_box() {
        let text = "[base]\nposition = [0.6, 0.35, 0.35]\n[[obstacle]]\nname = \"b\"\n\
            centre = [0.8, 0.0, 0.3]\nhalf_extents = [0.1, 0.02, 0.05]\n";
        let scene = Scene::from_toml(text, "t").expect("a valid scene");
        let outline = box_outline(&scene.boxes[0]);
        assert_eq!(outline.len(), 16);
        let mut corners: Vec<[i64; 3]> = outline
            .iter()
            .map(|p| p.map(|x| (x * 1e6).round() as i64))
            .collect();
        corners.sort_unstable();
        corners.dedup();
        assert_eq!(corners.len(), 8);
        for p in &outline {
            assert!(((p[0] - 0.8).abs() - 0.1).abs() < 1e-12);
            assert!(((p[1]).abs() - 0.02).abs() < 1e-12);
            assert!(((p[2] - 0.3).abs() - 0.05).abs() < 1e-12);
        }
    }
}
