//! The ROS 2 messages ftwire speaks, written by hand as serde structs.
//!
//! Each struct's fields are in the order of its `.msg` definition (ROS 2 Humble and Jazzy agree
//! on every type here), because CDR serialises fields in declaration order with no names. The
//! `TYPE_NAME` constants are the DDS type names ROS 2 publishes under (`pkg::msg::dds_::Type_`).
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
    /// `type`: a sphere.
    pub const SPHERE: i32 = 2;
    /// `type`: a line through `points`.
    pub const LINE_STRIP: i32 = 4;
    /// `action`: add or modify.
    pub const ADD: i32 = 0;
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

/// A message ftwire speaks: its ROS 2 type name (as in `ros2 topic info`) and definition text
/// (the `.msg` file, as an MCAP `ros2msg` schema holds it, dependencies included).
pub trait RosMessage: Serialize + for<'de> Deserialize<'de> {
    /// Package and type, such as `geometry_msgs/msg/WrenchStamped`.
    const TYPE_NAME: &'static str;
}

macro_rules! ros_message {
    ($($ty:ty => $name:literal),* $(,)?) => {
        $(impl RosMessage for $ty {
            const TYPE_NAME: &'static str = $name;
        })*
    };
}

ros_message! {
    Header => "std_msgs/msg/Header",
    WrenchStamped => "geometry_msgs/msg/WrenchStamped",
    PoseStamped => "geometry_msgs/msg/PoseStamped",
    Pose => "geometry_msgs/msg/Pose",
    Wrench => "geometry_msgs/msg/Wrench",
    Path => "nav_msgs/msg/Path",
    Marker => "visualization_msgs/msg/Marker",
    MarkerArray => "visualization_msgs/msg/MarkerArray",
}

/// `geometry_msgs/PoseArray`: poses in one frame, such as the motion-capture markers.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseArray {
    /// Time and frame.
    pub header: Header,
    /// The poses in `header.frame_id`.
    pub poses: Vec<Pose>,
}

/// `std_msgs/String`: one UTF-8 text, such as a node's JSON status.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StdString {
    /// The text.
    pub data: String,
}

ros_message! {
    PoseArray => "geometry_msgs/msg/PoseArray",
    StdString => "std_msgs/msg/String",
}
