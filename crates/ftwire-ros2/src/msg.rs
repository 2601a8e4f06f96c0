//! The ROS 2 messages ftwire speaks, written by hand as serde structs.
//!
//! Each struct's fields are in the order of its `.msg` definition, because CDR serialises
//! fields in declaration order with no names. ROS 2 Humble and Jazzy agree on every field of
//! every type here; `visualization_msgs/Marker`'s constant `ARROW_STRIP` is Jazzy's only, and
//! the definition text follows the `jazzy` feature. The `TYPE_NAME` constants are the DDS type
//! names ROS 2 publishes under (`pkg::msg::dds_::Type_`).
//! Units are SI: metres, newtons, newton-metres, seconds.

use serde::{Deserialize, Serialize};

/// `builtin_interfaces/Time`: seconds and nanoseconds since the epoch of the clock in use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, in 0..1e9.
    pub nanosec: u32,
}

/// `builtin_interfaces/Duration`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, in 0..1e9.
    pub nanosec: u32,
}

/// `std_msgs/Header`: when and in which frame.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Time of the data.
    pub stamp: Time,
    /// Frame the data is expressed in.
    pub frame_id: String,
}

/// `std_msgs/String`: one string (named `StringMsg` so as not to shadow Rust's `String`).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StringMsg {
    /// The text.
    pub data: String,
}

/// `std_msgs/ColorRGBA`, each channel in [0, 1].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ColorRGBA {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Opacity.
    pub a: f32,
}

/// `geometry_msgs/Vector3`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/Point` [m].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/Quaternion` (x, y, z, w), unit for an orientation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w (the scalar part).
    pub w: f64,
}

impl Default for Quaternion {
    /// The identity, as the message's defaults.
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// `geometry_msgs/Pose`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position [m].
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/PoseStamped`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseStamped {
    /// Time and frame.
    pub header: Header,
    /// The pose in `header.frame_id`.
    pub pose: Pose,
}

/// `geometry_msgs/PoseArray`: poses in one frame. ftwire's markers topic: one pose per
/// motion-capture marker, positions in the base clamp frame \[m\], in order along the wire
/// (marker 0 at the clamp); a NaN position is a dropout; orientations are unused.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseArray {
    /// Time and frame.
    pub header: Header,
    /// The poses in `header.frame_id`.
    pub poses: Vec<Pose>,
}

/// `geometry_msgs/Wrench`: force [N] and torque [N·m].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Wrench {
    /// Force [N].
    pub force: Vector3,
    /// Torque [N·m].
    pub torque: Vector3,
}

/// `geometry_msgs/WrenchStamped`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct WrenchStamped {
    /// Time and frame (the sensor's).
    pub header: Header,
    /// The wrench in `header.frame_id`.
    pub wrench: Wrench,
}

/// `nav_msgs/Path`: a sequence of poses, here the wire's centreline.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Path {
    /// Time and frame of the path.
    pub header: Header,
    /// The poses, from the base clamp to the tip.
    pub poses: Vec<PoseStamped>,
}

/// `sensor_msgs/CompressedImage` (a field of [`Marker`]; ftwire leaves it empty).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CompressedImage {
    /// Time and frame.
    pub header: Header,
    /// Image format, such as "png".
    pub format: String,
    /// The compressed bytes.
    pub data: Vec<u8>,
}

/// `visualization_msgs/UVCoordinate` (a field of [`Marker`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct UVCoordinate {
    /// u.
    pub u: f32,
    /// v.
    pub v: f32,
}

/// `visualization_msgs/MeshFile` (a field of [`Marker`]; ftwire leaves it empty).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshFile {
    /// File name.
    pub filename: String,
    /// File contents.
    pub data: Vec<u8>,
}

/// `visualization_msgs/Marker`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// Time and frame.
    pub header: Header,
    /// Namespace; with `id` it names the marker.
    pub ns: String,
    /// Id within the namespace.
    pub id: i32,
    /// One of the `Marker::*` shape constants, such as [`Marker::LINE_STRIP`].
    #[serde(rename = "type")]
    pub kind: i32,
    /// [`Marker::ADD`], [`Marker::DELETE`] or [`Marker::DELETEALL`].
    pub action: i32,
    /// Pose of the marker's frame.
    pub pose: Pose,
    /// Size [m]; for a line strip, `scale.x` is the line width.
    pub scale: Vector3,
    /// Colour of the whole marker.
    pub color: ColorRGBA,
    /// How long the marker lives; zero is forever.
    pub lifetime: Duration,
    /// Whether the marker moves with its frame.
    pub frame_locked: bool,
    /// Points of a line strip, list or points marker.
    pub points: Vec<Point>,
    /// One colour per point (or empty).
    pub colors: Vec<ColorRGBA>,
    /// Texture resource URI.
    pub texture_resource: String,
    /// Texture image.
    pub texture: CompressedImage,
    /// Texture coordinates.
    pub uv_coordinates: Vec<UVCoordinate>,
    /// Text of a text marker.
    pub text: String,
    /// Mesh resource URI.
    pub mesh_resource: String,
    /// Mesh file.
    pub mesh_file: MeshFile,
    /// Whether a mesh keeps its own materials.
    pub mesh_use_embedded_materials: bool,
}

impl Marker {
    /// `type`: an arrow.
    pub const ARROW: i32 = 0;
    /// `type`: a box.
    pub const CUBE: i32 = 1;
    /// `type`: a sphere.
    pub const SPHERE: i32 = 2;
    /// `type`: a cylinder.
    pub const CYLINDER: i32 = 3;
    /// `type`: a line through `points`.
    pub const LINE_STRIP: i32 = 4;
    /// `type`: a line segment per pair of `points`.
    pub const LINE_LIST: i32 = 5;
    /// `type`: a box at each of `points`.
    pub const CUBE_LIST: i32 = 6;
    /// `type`: a sphere at each of `points`.
    pub const SPHERE_LIST: i32 = 7;
    /// `type`: a square dot at each of `points`.
    pub const POINTS: i32 = 8;
    /// `type`: `text`, facing the viewer.
    pub const TEXT_VIEW_FACING: i32 = 9;
    /// `type`: the mesh of `mesh_resource`.
    pub const MESH_RESOURCE: i32 = 10;
    /// `type`: a triangle per three `points`.
    pub const TRIANGLE_LIST: i32 = 11;
    /// `type`: arrows along `points` (declared by Jazzy's message, not Humble's; not drawn by
    /// RViz).
    pub const ARROW_STRIP: i32 = 12;
    /// `action`: add or modify.
    pub const ADD: i32 = 0;
    /// `action`: the same as [`Marker::ADD`].
    pub const MODIFY: i32 = 0;
    /// `action`: delete this marker.
    pub const DELETE: i32 = 2;
    /// `action`: delete every marker.
    pub const DELETEALL: i32 = 3;
}

/// `visualization_msgs/MarkerArray`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MarkerArray {
    /// The markers.
    pub markers: Vec<Marker>,
}

/// `geometry_msgs/Transform`: a rigid motion, the child frame's pose in the parent frame
/// (`p_parent = rotation · p_child + translation`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation \[m\].
    pub translation: Vector3,
    /// Rotation, a unit quaternion.
    pub rotation: Quaternion,
}

/// `geometry_msgs/TransformStamped`: one edge of the TF tree, from `header.frame_id` (the
/// parent) to `child_frame_id`, at `header.stamp`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Time and the parent frame.
    pub header: Header,
    /// The child frame.
    pub child_frame_id: String,
    /// The child frame's pose in the parent frame.
    pub transform: Transform,
}

/// `tf2_msgs/TFMessage`: the message of `/tf` and `/tf_static`, any number of edges.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TFMessage {
    /// The edges.
    pub transforms: Vec<TransformStamped>,
}

/// A message ftwire speaks: its ROS 2 type name (as in `ros2 topic info`) and its complete
/// definition (the `.msg` text with every type it uses), as a bag's `ros2msg` schema holds it.
pub trait RosMessage: Serialize + for<'de> Deserialize<'de> {
    /// Package and type, such as `geometry_msgs/msg/WrenchStamped`.
    const TYPE_NAME: &'static str;
    /// The complete `ros2msg` definition, in rosbag2's layout: the type's `.msg` text, then for
    /// each type it uses (depth first, each package's names in sorted order, each type once) a
    /// line of 80 `=`, a line `MSG: pkg/Type` and that type's text. [`full_definition`] builds
    /// the same text from [`MSG_TEXTS`], as rosbag2 does from the installed `.msg` files.
    const DEFINITION: &'static str;
}

/// The line between two definitions of a `ros2msg` schema: 80 `=`.
pub const DEFINITION_SEPARATOR: &str =
    "================================================================================";

/// `visualization_msgs/Marker`'s constant `ARROW_STRIP`: Jazzy's `.msg` declares it, Humble's
/// does not (the fields, and so the bytes, are the same). Checked against both distributions'
/// definitions by `tests/rosbags_check.py`.
#[cfg(feature = "jazzy")]
macro_rules! marker_arrow_strip {
    () => {
        "int32 ARROW_STRIP=12\n"
    };
}

/// Humble's `visualization_msgs/Marker` has no `ARROW_STRIP` (see the `jazzy` version).
#[cfg(not(feature = "jazzy"))]
macro_rules! marker_arrow_strip {
    () => {
        ""
    };
}

/// The `.msg` text of each type, as `concat!` literals (comments and blank lines left out:
/// the fields, their types and the constants are what a reader of the schema needs).
macro_rules! msg_text {
    ("builtin_interfaces/Time") => {
        "int32 sec\nuint32 nanosec\n"
    };
    ("builtin_interfaces/Duration") => {
        "int32 sec\nuint32 nanosec\n"
    };
    ("std_msgs/Header") => {
        "builtin_interfaces/Time stamp\nstring frame_id\n"
    };
    ("std_msgs/String") => {
        "string data\n"
    };
    ("std_msgs/ColorRGBA") => {
        "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"
    };
    ("geometry_msgs/Vector3") => {
        "float64 x\nfloat64 y\nfloat64 z\n"
    };
    ("geometry_msgs/Point") => {
        "float64 x\nfloat64 y\nfloat64 z\n"
    };
    ("geometry_msgs/Quaternion") => {
        "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"
    };
    ("geometry_msgs/Pose") => {
        "Point position\nQuaternion orientation\n"
    };
    ("geometry_msgs/PoseStamped") => {
        "std_msgs/Header header\nPose pose\n"
    };
    ("geometry_msgs/PoseArray") => {
        "std_msgs/Header header\nPose[] poses\n"
    };
    ("geometry_msgs/Wrench") => {
        "Vector3 force\nVector3 torque\n"
    };
    ("geometry_msgs/WrenchStamped") => {
        "std_msgs/Header header\nWrench wrench\n"
    };
    ("nav_msgs/Path") => {
        "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n"
    };
    ("sensor_msgs/CompressedImage") => {
        "std_msgs/Header header\nstring format\nuint8[] data\n"
    };
    ("visualization_msgs/UVCoordinate") => {
        "float32 u\nfloat32 v\n"
    };
    ("visualization_msgs/MeshFile") => {
        "string filename\nuint8[] data\n"
    };
    ("visualization_msgs/Marker") => {
        concat!(
            "int32 ARROW=0\n",
            "int32 CUBE=1\n",
            "int32 SPHERE=2\n",
            "int32 CYLINDER=3\n",
            "int32 LINE_STRIP=4\n",
            "int32 LINE_LIST=5\n",
            "int32 CUBE_LIST=6\n",
            "int32 SPHERE_LIST=7\n",
            "int32 POINTS=8\n",
            "int32 TEXT_VIEW_FACING=9\n",
            "int32 MESH_RESOURCE=10\n",
            "int32 TRIANGLE_LIST=11\n",
            marker_arrow_strip!(),
            "int32 ADD=0\n",
            "int32 MODIFY=0\n",
            "int32 DELETE=2\n",
            "int32 DELETEALL=3\n",
            "std_msgs/Header header\n",
            "string ns\n",
            "int32 id\n",
            "int32 type\n",
            "int32 action\n",
            "geometry_msgs/Pose pose\n",
            "geometry_msgs/Vector3 scale\n",
            "std_msgs/ColorRGBA color\n",
            "builtin_interfaces/Duration lifetime\n",
            "bool frame_locked\n",
            "geometry_msgs/Point[] points\n",
            "std_msgs/ColorRGBA[] colors\n",
            "string texture_resource\n",
            "sensor_msgs/CompressedImage texture\n",
            "UVCoordinate[] uv_coordinates\n",
            "string text\n",
            "string mesh_resource\n",
            "MeshFile mesh_file\n",
            "bool mesh_use_embedded_materials\n",
        )
    };
    ("visualization_msgs/MarkerArray") => {
        "Marker[] markers\n"
    };
    ("geometry_msgs/Transform") => {
        "Vector3 translation\nQuaternion rotation\n"
    };
    ("geometry_msgs/TransformStamped") => {
        "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"
    };
    ("tf2_msgs/TFMessage") => {
        "geometry_msgs/TransformStamped[] transforms\n"
    };
}

/// The `.msg` text of every type here, by its package resource name (`pkg/Type`, the name a
/// `ros2msg` schema's `MSG:` lines use). Comments and blank lines are left out.
pub const MSG_TEXTS: &[(&str, &str)] = &[
    (
        "builtin_interfaces/Time",
        msg_text!("builtin_interfaces/Time"),
    ),
    (
        "builtin_interfaces/Duration",
        msg_text!("builtin_interfaces/Duration"),
    ),
    ("std_msgs/Header", msg_text!("std_msgs/Header")),
    ("std_msgs/String", msg_text!("std_msgs/String")),
    ("std_msgs/ColorRGBA", msg_text!("std_msgs/ColorRGBA")),
    ("geometry_msgs/Vector3", msg_text!("geometry_msgs/Vector3")),
    ("geometry_msgs/Point", msg_text!("geometry_msgs/Point")),
    (
        "geometry_msgs/Quaternion",
        msg_text!("geometry_msgs/Quaternion"),
    ),
    ("geometry_msgs/Pose", msg_text!("geometry_msgs/Pose")),
    (
        "geometry_msgs/PoseStamped",
        msg_text!("geometry_msgs/PoseStamped"),
    ),
    (
        "geometry_msgs/PoseArray",
        msg_text!("geometry_msgs/PoseArray"),
    ),
    ("geometry_msgs/Wrench", msg_text!("geometry_msgs/Wrench")),
    (
        "geometry_msgs/WrenchStamped",
        msg_text!("geometry_msgs/WrenchStamped"),
    ),
    ("nav_msgs/Path", msg_text!("nav_msgs/Path")),
    (
        "sensor_msgs/CompressedImage",
        msg_text!("sensor_msgs/CompressedImage"),
    ),
    (
        "visualization_msgs/UVCoordinate",
        msg_text!("visualization_msgs/UVCoordinate"),
    ),
    (
        "visualization_msgs/MeshFile",
        msg_text!("visualization_msgs/MeshFile"),
    ),
    (
        "visualization_msgs/Marker",
        msg_text!("visualization_msgs/Marker"),
    ),
    (
        "visualization_msgs/MarkerArray",
        msg_text!("visualization_msgs/MarkerArray"),
    ),
    (
        "geometry_msgs/Transform",
        msg_text!("geometry_msgs/Transform"),
    ),
    (
        "geometry_msgs/TransformStamped",
        msg_text!("geometry_msgs/TransformStamped"),
    ),
    ("tf2_msgs/TFMessage", msg_text!("tf2_msgs/TFMessage")),
];

/// The complete `ros2msg` definition of `root` (`pkg/Type` or `pkg/msg/Type`) from
/// [`MSG_TEXTS`], built as rosbag2 builds it: the root's text, then each type it uses, depth
/// first; a type's dependencies are the non-primitive field types of its text (a name without
/// a package is in the type's own package), visited in sorted order, each type once, each
/// preceded by a newline, [`DEFINITION_SEPARATOR`], a newline and `MSG: pkg/Type`. `None` if
/// `root` or a type it uses is not in [`MSG_TEXTS`].
///
/// # Example
/// ```
/// use ftwire_ros2::msg::{RosMessage, WrenchStamped, full_definition};
/// let text = full_definition("geometry_msgs/msg/WrenchStamped");
/// assert_eq!(text.as_deref(), Some(WrenchStamped::DEFINITION));
/// ```
pub fn full_definition(root: &str) -> Option<String> {
    fn text_of(name: &str) -> Option<&'static str> {
        MSG_TEXTS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
    }
    fn dependencies(name: &str, text: &str) -> std::collections::BTreeSet<String> {
        const PRIMITIVES: [&str; 14] = [
            "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
            "int32", "uint32", "int64", "uint64", "string",
        ];
        let package = name.split('/').next().unwrap_or_default();
        text.lines()
            .filter_map(|line| line.split_whitespace().next())
            .filter(|word| !word.starts_with('#'))
            .map(|word| word.split('[').next().unwrap_or(word))
            .filter(|ty| !PRIMITIVES.contains(ty))
            .map(|ty| {
                if ty.contains('/') {
                    ty.to_string()
                } else {
                    format!("{package}/{ty}")
                }
            })
            .collect()
    }
    fn append(
        name: &str,
        seen: &mut std::collections::BTreeSet<String>,
        out: &mut String,
    ) -> Option<()> {
        let text = text_of(name)?;
        out.push_str(text);
        for dependency in dependencies(name, text) {
            if seen.insert(dependency.clone()) {
                out.push('\n');
                out.push_str(DEFINITION_SEPARATOR);
                out.push_str("\nMSG: ");
                out.push_str(&dependency);
                out.push('\n');
                append(&dependency, seen, out)?;
            }
        }
        Some(())
    }
    let name = root.replacen("/msg/", "/", 1);
    let mut out = String::new();
    append(&name, &mut std::collections::BTreeSet::new(), &mut out)?;
    Some(out)
}

macro_rules! ros_message {
    ($($ty:ty => $type_name:literal, $root:tt $(, $dependency:tt)*;)*) => {
        $(impl RosMessage for $ty {
            const TYPE_NAME: &'static str = $type_name;
            const DEFINITION: &'static str = concat!(
                msg_text!($root),
                $("\n================================================================================\nMSG: ",
                $dependency,
                "\n",
                msg_text!($dependency),)*
            );
        })*
    };
}

ros_message! {
    Time => "builtin_interfaces/msg/Time", "builtin_interfaces/Time";
    Duration => "builtin_interfaces/msg/Duration", "builtin_interfaces/Duration";
    Header => "std_msgs/msg/Header", "std_msgs/Header", "builtin_interfaces/Time";
    StringMsg => "std_msgs/msg/String", "std_msgs/String";
    ColorRGBA => "std_msgs/msg/ColorRGBA", "std_msgs/ColorRGBA";
    Vector3 => "geometry_msgs/msg/Vector3", "geometry_msgs/Vector3";
    Point => "geometry_msgs/msg/Point", "geometry_msgs/Point";
    Quaternion => "geometry_msgs/msg/Quaternion", "geometry_msgs/Quaternion";
    Pose => "geometry_msgs/msg/Pose", "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion";
    PoseStamped => "geometry_msgs/msg/PoseStamped", "geometry_msgs/PoseStamped", "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion", "std_msgs/Header", "builtin_interfaces/Time";
    PoseArray => "geometry_msgs/msg/PoseArray", "geometry_msgs/PoseArray", "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion", "std_msgs/Header", "builtin_interfaces/Time";
    Wrench => "geometry_msgs/msg/Wrench", "geometry_msgs/Wrench", "geometry_msgs/Vector3";
    WrenchStamped => "geometry_msgs/msg/WrenchStamped", "geometry_msgs/WrenchStamped", "geometry_msgs/Wrench", "geometry_msgs/Vector3", "std_msgs/Header", "builtin_interfaces/Time";
    Path => "nav_msgs/msg/Path", "nav_msgs/Path", "geometry_msgs/PoseStamped", "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion", "std_msgs/Header", "builtin_interfaces/Time";
    CompressedImage => "sensor_msgs/msg/CompressedImage", "sensor_msgs/CompressedImage", "std_msgs/Header", "builtin_interfaces/Time";
    UVCoordinate => "visualization_msgs/msg/UVCoordinate", "visualization_msgs/UVCoordinate";
    MeshFile => "visualization_msgs/msg/MeshFile", "visualization_msgs/MeshFile";
    Marker => "visualization_msgs/msg/Marker", "visualization_msgs/Marker", "builtin_interfaces/Duration", "geometry_msgs/Point", "geometry_msgs/Pose", "geometry_msgs/Quaternion", "geometry_msgs/Vector3", "sensor_msgs/CompressedImage", "std_msgs/Header", "builtin_interfaces/Time", "std_msgs/ColorRGBA", "visualization_msgs/MeshFile", "visualization_msgs/UVCoordinate";
    MarkerArray => "visualization_msgs/msg/MarkerArray", "visualization_msgs/MarkerArray", "visualization_msgs/Marker", "builtin_interfaces/Duration", "geometry_msgs/Point", "geometry_msgs/Pose", "geometry_msgs/Quaternion", "geometry_msgs/Vector3", "sensor_msgs/CompressedImage", "std_msgs/Header", "builtin_interfaces/Time", "std_msgs/ColorRGBA", "visualization_msgs/MeshFile", "visualization_msgs/UVCoordinate";
    Transform => "geometry_msgs/msg/Transform", "geometry_msgs/Transform", "geometry_msgs/Quaternion", "geometry_msgs/Vector3";
    TransformStamped => "geometry_msgs/msg/TransformStamped", "geometry_msgs/TransformStamped", "geometry_msgs/Transform", "geometry_msgs/Quaternion", "geometry_msgs/Vector3", "std_msgs/Header", "builtin_interfaces/Time";
    TFMessage => "tf2_msgs/msg/TFMessage", "tf2_msgs/TFMessage", "geometry_msgs/TransformStamped", "geometry_msgs/Transform", "geometry_msgs/Quaternion", "geometry_msgs/Vector3", "std_msgs/Header", "builtin_interfaces/Time";
}
