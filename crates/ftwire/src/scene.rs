//! A planning scene's obstacles for the simulator: the planner (`ftwire-plan`) and the
//! ground truth (`ftwire-sim`) read the same scene file, and this is the one place that turns
//! it into the simulator's [`Obstacle`]s (only the binary sees both sides of the wall).
//!
//! Frames: the scene's poses are in the robot's world frame, the frame of the rig's gripper
//! poses, which is the simulator's world frame.

use ftwire_plan::Scene;
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
/// let obstacles = ftwire::scene::sim_obstacles(&scene)?;
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
