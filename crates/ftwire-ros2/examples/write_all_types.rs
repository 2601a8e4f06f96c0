//! Writes a ROS 2 bag with one message of every type of `ftwire_ros2::msg`, each with known
//! values, for an independent reader to check: `tests/rosbags_check.py` reads it with the
//! `rosbags` package and the official Humble and Jazzy message definitions.
//!
//! ```sh
//! cargo run --release -p ftwire-ros2 --example write_all_types -- DIR
//! ```
//!
//! writes `DIR/all_types.mcap` and `DIR/all_types.json`: for each topic, its type, the QoS its
//! channel carries and the message's field values (the structs serialised by serde, so the
//! field names are this crate's), plus the distribution the crate was built for.

use std::path::PathBuf;

use ftwire_ros2::bag::BagWriter;
use ftwire_ros2::msg::*;
use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use serde_json::{Value, json};

fn header(sec: i32, frame: &str) -> Header {
    Header {
        stamp: Time {
            sec,
            nanosec: 123_456_789,
        },
        frame_id: frame.into(),
    }
}

fn point(x: f64, y: f64, z: f64) -> Point {
    Point { x, y, z }
}

fn vector(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3 { x, y, z }
}

/// A unit quaternion (x, y, z, w) with every component non-zero.
fn turn() -> Quaternion {
    Quaternion {
        x: 0.1,
        y: -0.3,
        z: 0.5,
        w: (1.0f64 - 0.01 - 0.09 - 0.25).sqrt(),
    }
}

fn pose(x: f64) -> Pose {
    Pose {
        position: point(x, -0.25, 1e-3),
        orientation: turn(),
    }
}

fn color(r: f32) -> ColorRGBA {
    ColorRGBA {
        r,
        g: 0.5,
        b: 0.25,
        a: 1.0,
    }
}

fn transform_stamped(child: &str, x: f64) -> TransformStamped {
    TransformStamped {
        header: header(5, "world"),
        child_frame_id: child.into(),
        transform: Transform {
            translation: vector(x, 0.2, -0.3),
            rotation: turn(),
        },
    }
}

fn marker() -> Marker {
    Marker {
        header: header(9, "wire_base"),
        ns: "wire".into(),
        id: -7,
        kind: Marker::LINE_STRIP,
        action: Marker::DELETE,
        pose: pose(0.5),
        scale: vector(0.004, 0.0, 2.5),
        color: color(0.75),
        lifetime: Duration {
            sec: 2,
            nanosec: 500,
        },
        frame_locked: true,
        points: vec![point(0.0, 0.0, 0.0), point(0.1, 0.2, 0.3)],
        colors: vec![color(0.125), color(1.0)],
        texture_resource: "package://ftwire/tex.png".into(),
        texture: CompressedImage {
            header: header(1, "cam"),
            format: "png".into(),
            data: vec![137, 80, 78, 71],
        },
        uv_coordinates: vec![UVCoordinate { u: 0.25, v: 0.75 }],
        text: "Drähte".into(),
        mesh_resource: "file:///mesh.stl".into(),
        mesh_file: MeshFile {
            filename: "mesh.stl".into(),
            data: vec![0, 255, 1],
        },
        mesh_use_embedded_materials: true,
    }
}

/// The QoS of the topic: `/tf_static` as tf2 publishes it, one best-effort topic, the rest
/// reliable and volatile.
fn qos_of(topic: &str) -> QosProfile {
    let base = QosProfile::publisher_default().reliability_reliable(WhenFull::DEFAULT);
    match topic {
        "/tf_static" => base
            .durability(Durability::TransientLocal)
            .history(History::KeepLast { depth: 1 }),
        "/ft_sensor/wrench" => QosProfile::subscription_default()
            .reliability(Reliability::BestEffort)
            .history(History::KeepLast { depth: 1000 }),
        _ => base.history(History::KeepLast { depth: 10 }),
    }
}

/// Writes `message` on `topic` and returns its entry of the JSON.
fn write<M: RosMessage>(
    bag: &mut BagWriter,
    time: &mut u64,
    topic: &str,
    message: &M,
) -> Result<Value, Box<dyn std::error::Error>> {
    let qos = qos_of(topic);
    bag.set_qos(topic, &qos)?;
    *time += 1_000_000;
    bag.write(topic, *time, message)?;
    Ok(json!({
        "topic": topic,
        "type": M::TYPE_NAME,
        "reliability": if matches!(qos.reliability, Reliability::Reliable { .. }) {
            "reliable"
        } else {
            "best_effort"
        },
        "durability": if qos.durability == Durability::TransientLocal {
            "transient_local"
        } else {
            "volatile"
        },
        "value": serde_json::to_value(message)?,
    }))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: write_all_types DIR (writes DIR/all_types.mcap and .json)")?,
    );
    std::fs::create_dir_all(&dir)?;
    // Never replaces a file: DIR must not hold the two files yet.
    let known = dir.join("all_types.json");
    if known.exists() {
        return Err(format!("{} exists: give a new DIR", known.display()).into());
    }
    let mut bag = BagWriter::create(dir.join("all_types.mcap"), false)?;
    let entries = write_every_type(&mut bag)?;
    bag.finish()?;
    let distro = if cfg!(feature = "jazzy") {
        "jazzy"
    } else {
        "humble"
    };
    let count = entries.len();
    let text = serde_json::to_string_pretty(&json!({ "distro": distro, "topics": entries }))?;
    std::fs::write(dir.join("all_types.json"), text)?;
    println!(
        "wrote {count} messages into {}",
        dir.join("all_types.mcap").display()
    );
    Ok(())
}

/// One message of every type, each on its own topic; their known values.
fn write_every_type(
    b: &mut BagWriter,
) -> Result<Vec<serde_json::Value>, Box<dyn std::error::Error>> {
    let mut time = 1_700_000_000_000_000_000u64;
    let t = &mut time;
    let mut entries = vec![
        write(
            b,
            t,
            "/time",
            &Time {
                sec: -2,
                nanosec: 999_999_999,
            },
        )?,
        write(b, t, "/duration", &Duration { sec: 3, nanosec: 4 })?,
        write(b, t, "/header", &header(1, "wire_base"))?,
        write(
            b,
            t,
            "/string",
            &StringMsg {
                data: "ã = Γ⁻¹(b)".into(),
            },
        )?,
        write(b, t, "/color", &color(0.125))?,
        write(b, t, "/vector3", &vector(1.5, -2.25, 1e-9))?,
        write(b, t, "/point", &point(0.1, 0.2, 0.3))?,
        write(b, t, "/quaternion", &turn())?,
        write(b, t, "/pose", &pose(0.6))?,
        write(
            b,
            t,
            "/wire/tip_pose",
            &PoseStamped {
                header: header(2, "wire_base"),
                pose: pose(0.7),
            },
        )?,
        write(
            b,
            t,
            "/wire/markers",
            &PoseArray {
                header: header(3, "wire_base"),
                poses: vec![pose(0.1), pose(0.2), pose(0.3)],
            },
        )?,
    ];
    entries.extend(write_the_rest(b, t)?);
    Ok(entries)
}

/// The second half of [`write_every_type`].
fn write_the_rest(
    b: &mut BagWriter,
    t: &mut u64,
) -> Result<Vec<serde_json::Value>, Box<dyn std::error::Error>> {
    Ok(vec![
        write(
            b,
            t,
            "/wrench",
            &Wrench {
                force: vector(1.0, -2.0, 3.0),
                torque: vector(0.01, -0.02, 0.03),
            },
        )?,
        write(
            b,
            t,
            "/ft_sensor/wrench",
            &WrenchStamped {
                header: header(4, "ft_sensor"),
                wrench: Wrench {
                    force: vector(-0.5, 0.25, 9.81),
                    torque: vector(0.1, 0.2, -0.3),
                },
            },
        )?,
        write(
            b,
            t,
            "/wire/shape",
            &Path {
                header: header(6, "wire_base"),
                poses: vec![
                    PoseStamped {
                        header: header(6, "wire_base"),
                        pose: pose(0.0),
                    },
                    PoseStamped {
                        header: header(6, "a"),
                        pose: pose(0.4),
                    },
                ],
            },
        )?,
        write(
            b,
            t,
            "/image",
            &CompressedImage {
                header: header(7, "cam"),
                format: "jpeg".into(),
                data: vec![255, 216, 255, 0, 1],
            },
        )?,
        write(b, t, "/uv", &UVCoordinate { u: 0.5, v: -0.25 })?,
        write(
            b,
            t,
            "/mesh",
            &MeshFile {
                filename: "clamp.dae".into(),
                data: vec![7, 8, 9],
            },
        )?,
        write(b, t, "/marker", &marker())?,
        write(
            b,
            t,
            "/wire/markers_viz",
            &MarkerArray {
                markers: vec![marker(), Marker::default()],
            },
        )?,
        write(
            b,
            t,
            "/transform",
            &Transform {
                translation: vector(0.3, 0.0, -1.0),
                rotation: turn(),
            },
        )?,
        write(
            b,
            t,
            "/transform_stamped",
            &transform_stamped("wire_tip", 0.9),
        )?,
        write(
            b,
            t,
            "/tf",
            &TFMessage {
                transforms: vec![
                    transform_stamped("wire_tip", 0.8),
                    transform_stamped("c", 0.7),
                ],
            },
        )?,
        write(
            b,
            t,
            "/tf_static",
            &TFMessage {
                transforms: vec![transform_stamped("wire_base", 0.0)],
            },
        )?,
    ])
}
