//! The exact bytes ROS 2 puts on the wire per message type, written by hand from the `.msg`
//! definitions: header `00 01 00 00` (CDR little-endian), then the fields in order, each aligned
//! to its size from the body's start (offsets in the comments), strings as length (with NUL),
//! bytes, NUL; sequences as count, elements. A wrong field order, type or alignment shows.

use std::fmt::Debug;

use ftwire_ros2::cdr::{self, CdrError};
use ftwire_ros2::msg::*;

/// The encapsulation header: plain CDR, little-endian, no options.
const HDR: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// A `float64`, little-endian (the encoding of a number, not of a layout).
fn f64le(x: f64) -> [u8; 8] {
    x.to_le_bytes()
}

/// A `float32`, little-endian.
fn f32le(x: f32) -> [u8; 4] {
    x.to_le_bytes()
}

/// Encoding `message` gives `expected`, and decoding `expected` gives `message` back.
fn golden<M: RosMessage + PartialEq + Debug>(message: &M, expected: &[&[u8]]) {
    let expected = expected.concat();
    let bytes = cdr::encode(message).expect("encodes");
    assert_eq!(bytes, expected, "{}: the bytes differ", M::TYPE_NAME);
    let back: M = cdr::decode(&expected).expect("decodes");
    assert_eq!(&back, message, "{}: decoding differs", M::TYPE_NAME);
}

fn identity() -> Pose {
    Pose::default()
}

#[test]
fn time() {
    golden(
        &Time {
            sec: -2,
            nanosec: 300_000_000,
        },
        &[
            &HDR,
            &[0xFE, 0xFF, 0xFF, 0xFF], // 0: sec = -2 (int32)
            &[0x00, 0xA3, 0xE1, 0x11], // 4: nanosec = 300 000 000 = 0x11E1A300 (uint32)
        ],
    );
}

#[test]
fn duration() {
    golden(
        &Duration { sec: 5, nanosec: 7 },
        &[
            &HDR,
            &[5, 0, 0, 0], // 0: sec
            &[7, 0, 0, 0], // 4: nanosec
        ],
    );
}

#[test]
fn header() {
    golden(
        &Header {
            stamp: Time { sec: 1, nanosec: 2 },
            frame_id: "base".into(),
        },
        &[
            &HDR,
            &[1, 0, 0, 0],                // 0: stamp.sec
            &[2, 0, 0, 0],                // 4: stamp.nanosec
            &[5, 0, 0, 0],                // 8: frame_id length, NUL included
            &[b'b', b'a', b's', b'e', 0], // 12: "base" NUL; ends at 17
        ],
    );
}

#[test]
fn string() {
    golden(
        &StringMsg { data: "hi".into() },
        &[
            &HDR,
            &[3, 0, 0, 0],    // 0: length
            &[b'h', b'i', 0], // 4: "hi" NUL
        ],
    );
}

#[test]
fn color_rgba() {
    golden(
        &ColorRGBA {
            r: 1.0,
            g: 0.5,
            b: 0.25,
            a: 1.0,
        },
        &[
            &HDR,
            &[0x00, 0x00, 0x80, 0x3F], // 0: r = 1.0 (float32)
            &[0x00, 0x00, 0x00, 0x3F], // 4: g = 0.5
            &[0x00, 0x00, 0x80, 0x3E], // 8: b = 0.25
            &[0x00, 0x00, 0x80, 0x3F], // 12: a = 1.0
        ],
    );
}

#[test]
fn vector3() {
    golden(
        &Vector3 {
            x: 1.0,
            y: 2.0,
            z: 3.0,
        },
        &[
            &HDR,
            &[0, 0, 0, 0, 0, 0, 0xF0, 0x3F], // 0: x = 1.0 (float64)
            &[0, 0, 0, 0, 0, 0, 0x00, 0x40], // 8: y = 2.0
            &[0, 0, 0, 0, 0, 0, 0x08, 0x40], // 16: z = 3.0
        ],
    );
}

#[test]
fn point() {
    golden(
        &Point {
            x: -1.5,
            y: 0.0,
            z: 0.25,
        },
        &[
            &HDR,
            &[0, 0, 0, 0, 0, 0, 0xF8, 0xBF], // 0: x = -1.5
            &[0; 8],                         // 8: y = 0
            &[0, 0, 0, 0, 0, 0, 0xD0, 0x3F], // 16: z = 0.25
        ],
    );
}

#[test]
fn quaternion() {
    golden(
        &Quaternion::default(),
        &[
            &HDR,
            &[0; 8],                         // 0: x
            &[0; 8],                         // 8: y
            &[0; 8],                         // 16: z
            &[0, 0, 0, 0, 0, 0, 0xF0, 0x3F], // 24: w = 1, last
        ],
    );
}

#[test]
fn pose() {
    let pose = Pose {
        position: Point {
            x: 1.0,
            y: 2.0,
            z: 3.0,
        },
        orientation: Quaternion {
            x: 0.5,
            y: -0.5,
            z: 0.5,
            w: -0.5,
        },
    };
    golden(
        &pose,
        &[
            &HDR,
            &f64le(1.0), // 0: position.x
            &f64le(2.0), // 8: position.y
            &f64le(3.0), // 16: position.z
            &f64le(0.5), // 24: orientation.x
            &f64le(-0.5),
            &f64le(0.5),
            &f64le(-0.5), // 48: orientation.w
        ],
    );
}

#[test]
fn pose_stamped() {
    let message = PoseStamped {
        header: Header {
            stamp: Time {
                sec: 10,
                nanosec: 20,
            },
            frame_id: "base".into(),
        },
        pose: Pose {
            position: Point {
                x: 0.6,
                y: 0.05,
                z: -0.01,
            },
            orientation: Quaternion::default(),
        },
    };
    golden(
        &message,
        &[
            &HDR,
            &[10, 0, 0, 0],               // 0: header.stamp.sec
            &[20, 0, 0, 0],               // 4: header.stamp.nanosec
            &[5, 0, 0, 0],                // 8: frame_id length
            &[b'b', b'a', b's', b'e', 0], // 12: "base" NUL, to 17
            &[0; 7],                      // 17: padding to 24, float64 alignment from the body
            &f64le(0.6),                  // 24: pose.position.x
            &f64le(0.05),
            &f64le(-0.01),
            &f64le(0.0), // 48: pose.orientation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(1.0), // 72: pose.orientation.w
        ],
    );
}

#[test]
fn pose_array() {
    let p = |x: f64| Pose {
        position: Point { x, y: 0.0, z: 0.0 },
        orientation: Quaternion::default(),
    };
    let message = PoseArray {
        header: Header::default(),
        poses: vec![p(0.1), p(f64::NAN)],
    };
    let expected: Vec<&[u8]> = vec![
        &HDR,
        &[0, 0, 0, 0], // 0: header.stamp.sec
        &[0, 0, 0, 0], // 4: header.stamp.nanosec
        &[1, 0, 0, 0], // 8: frame_id length 1: the empty string is its NUL
        &[0],          // 12: NUL, to 13
        &[0, 0, 0],    // 13: padding to 16, uint32 alignment
        &[2, 0, 0, 0], // 16: poses count = 2
        &[0; 4],       // 20: padding to 24, float64 alignment
    ];
    let first = [
        f64le(0.1), // 24: poses[0].position.x
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(1.0), // 72: poses[0].orientation.w
    ]
    .concat();
    let second = [
        f64le(f64::NAN), // 80: poses[1].position.x, a dropout
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(0.0),
        f64le(1.0),
    ]
    .concat();
    let expected = [expected.concat(), first, second].concat();
    // NaN != NaN: compare bytes, and the decoded message field by field.
    assert_eq!(cdr::encode(&message).expect("encodes"), expected);
    let back: PoseArray = cdr::decode(&expected).expect("decodes");
    assert_eq!(back.poses.len(), 2);
    assert_eq!(back.poses[0], message.poses[0]);
    assert!(back.poses[1].position.x.is_nan());
}

#[test]
fn wrench() {
    let message = Wrench {
        force: Vector3 {
            x: 1.0,
            y: -2.0,
            z: 3.0,
        },
        torque: Vector3 {
            x: 0.1,
            y: -0.2,
            z: 0.3,
        },
    };
    golden(
        &message,
        &[
            &HDR,
            &f64le(1.0), // 0: force.x: force first
            &f64le(-2.0),
            &f64le(3.0),
            &f64le(0.1), // 24: torque.x
            &f64le(-0.2),
            &f64le(0.3),
        ],
    );
}

#[test]
fn wrench_stamped() {
    let message = WrenchStamped {
        header: Header {
            stamp: Time {
                sec: 1,
                nanosec: 500,
            },
            frame_id: "ft".into(),
        },
        wrench: Wrench {
            force: Vector3 {
                x: 1.0,
                y: 2.0,
                z: 3.0,
            },
            torque: Vector3 {
                x: 4.0,
                y: 5.0,
                z: 6.0,
            },
        },
    };
    golden(
        &message,
        &[
            &HDR,
            &[1, 0, 0, 0],       // 0: stamp.sec
            &[0xF4, 0x01, 0, 0], // 4: stamp.nanosec = 500
            &[3, 0, 0, 0],       // 8: frame_id length
            &[b'f', b't', 0],    // 12: "ft" NUL, to 15
            &[0],                // 15: padding to 16
            &f64le(1.0),         // 16: force.x
            &f64le(2.0),
            &f64le(3.0),
            &f64le(4.0), // 40: torque.x
            &f64le(5.0),
            &f64le(6.0),
        ],
    );
}

#[test]
fn path() {
    let message = Path {
        header: Header {
            stamp: Time::default(),
            frame_id: "map".into(),
        },
        poses: vec![PoseStamped {
            header: Header {
                stamp: Time { sec: 3, nanosec: 4 },
                frame_id: "a".into(),
            },
            pose: identity(),
        }],
    };
    golden(
        &message,
        &[
            &HDR,
            &[0; 8],                // 0: header.stamp
            &[4, 0, 0, 0],          // 8: frame_id length
            &[b'm', b'a', b'p', 0], // 12: "map" NUL, to 16
            &[1, 0, 0, 0],          // 16: poses count = 1
            &[3, 0, 0, 0],          // 20: poses[0].header.stamp.sec
            &[4, 0, 0, 0],          // 24: poses[0].header.stamp.nanosec
            &[2, 0, 0, 0],          // 28: frame_id length
            &[b'a', 0],             // 32: "a" NUL, to 34
            &[0; 6],                // 34: padding to 40
            &[0; 48],               // 40: position and orientation x, y, z = 0
            &f64le(1.0),            // 88: orientation.w
        ],
    );
}

#[test]
fn compressed_image() {
    let message = CompressedImage {
        header: Header::default(),
        format: "png".into(),
        data: vec![1, 2, 3],
    };
    golden(
        &message,
        &[
            &HDR,
            &[0; 8],                // 0: header.stamp
            &[1, 0, 0, 0],          // 8: frame_id length 1
            &[0],                   // 12: NUL, to 13
            &[0, 0, 0],             // 13: padding to 16
            &[4, 0, 0, 0],          // 16: format length
            &[b'p', b'n', b'g', 0], // 20: "png" NUL, to 24
            &[3, 0, 0, 0],          // 24: data count
            &[1, 2, 3],             // 28: data (uint8, no alignment), to 31
        ],
    );
}

#[test]
fn uv_coordinate() {
    golden(
        &UVCoordinate { u: 0.5, v: 0.25 },
        &[
            &HDR,
            &f32le(0.5),  // 0: u (float32)
            &f32le(0.25), // 4: v
        ],
    );
}

#[test]
fn mesh_file() {
    golden(
        &MeshFile {
            filename: "m".into(),
            data: vec![9],
        },
        &[
            &HDR,
            &[2, 0, 0, 0], // 0: filename length
            &[b'm', 0],    // 4: "m" NUL, to 6
            &[0, 0],       // 6: padding to 8
            &[1, 0, 0, 0], // 8: data count
            &[9],          // 12: data
        ],
    );
}

#[test]
fn marker() {
    let message = Marker {
        header: Header {
            stamp: Time::default(),
            frame_id: "b".into(),
        },
        ns: "w".into(),
        id: 7,
        kind: Marker::LINE_STRIP,
        action: Marker::ADD,
        pose: identity(),
        scale: Vector3 {
            x: 0.002,
            y: 0.0,
            z: 0.0,
        },
        color: ColorRGBA {
            r: 1.0,
            g: 0.0,
            b: 0.0,
            a: 1.0,
        },
        points: vec![
            Point::default(),
            Point {
                x: 0.5,
                y: 0.0,
                z: 0.0,
            },
        ],
        ..Marker::default()
    };
    golden(
        &message,
        &[
            &HDR,
            &[0; 8],       // 0: header.stamp
            &[2, 0, 0, 0], // 8: frame_id length
            &[b'b', 0],    // 12: "b" NUL, to 14
            &[0, 0],       // 14: padding to 16
            &[2, 0, 0, 0], // 16: ns length
            &[b'w', 0],    // 20: "w" NUL, to 22
            &[0, 0],       // 22: padding to 24
            &[7, 0, 0, 0], // 24: id
            &[4, 0, 0, 0], // 28: type = LINE_STRIP
            &[0, 0, 0, 0], // 32: action = ADD
            &[0; 4],       // 36: padding to 40
            &[0; 48],      // 40: pose: position, orientation x, y, z
            &f64le(1.0),   // 88: pose.orientation.w
            &f64le(0.002), // 96: scale.x
            &[0; 16],      // 104: scale.y, z
            &f32le(1.0),   // 120: color.r
            &f32le(0.0),   // 124: color.g
            &f32le(0.0),   // 128: color.b
            &f32le(1.0),   // 132: color.a
            &[0; 8],       // 136: lifetime
            &[0],          // 144: frame_locked = false
            &[0, 0, 0],    // 145: padding to 148
            &[2, 0, 0, 0], // 148: points count
            &[0; 24],      // 152: points[0]
            &f64le(0.5),   // 176: points[1].x
            &[0; 16],      // 184: points[1].y, z
            &[0, 0, 0, 0], // 200: colors count = 0
            &[1, 0, 0, 0], // 204: texture_resource length 1
            &[0],          // 208: NUL, to 209
            &[0, 0, 0],    // 209: padding to 212
            &[0; 8],       // 212: texture.header.stamp
            &[1, 0, 0, 0], // 220: texture.header.frame_id length
            &[0],          // 224: NUL, to 225
            &[0, 0, 0],    // 225: padding to 228
            &[1, 0, 0, 0], // 228: texture.format length
            &[0],          // 232: NUL, to 233
            &[0, 0, 0],    // 233: padding to 236
            &[0, 0, 0, 0], // 236: texture.data count
            &[0, 0, 0, 0], // 240: uv_coordinates count
            &[1, 0, 0, 0], // 244: text length
            &[0],          // 248: NUL, to 249
            &[0, 0, 0],    // 249: padding to 252
            &[1, 0, 0, 0], // 252: mesh_resource length
            &[0],          // 256: NUL, to 257
            &[0, 0, 0],    // 257: padding to 260
            &[1, 0, 0, 0], // 260: mesh_file.filename length
            &[0],          // 264: NUL, to 265
            &[0, 0, 0],    // 265: padding to 268
            &[0, 0, 0, 0], // 268: mesh_file.data count
            &[0],          // 272: mesh_use_embedded_materials = false; 273 bytes
        ],
    );
}

#[test]
fn marker_array() {
    // One default marker, starting at body offset 4: its alignment differs from `marker`'s.
    let message = MarkerArray {
        markers: vec![Marker::default()],
    };
    golden(
        &message,
        &[
            &HDR,
            &[1, 0, 0, 0], // 0: markers count
            &[0; 8],       // 4: header.stamp
            &[1, 0, 0, 0], // 12: frame_id length
            &[0],          // 16: NUL, to 17
            &[0, 0, 0],    // 17: padding to 20
            &[1, 0, 0, 0], // 20: ns length
            &[0],          // 24: NUL, to 25
            &[0, 0, 0],    // 25: padding to 28
            &[0; 4],       // 28: id
            &[0; 4],       // 32: type
            &[0; 4],       // 36: action
            &[0; 48],      // 40: pose (no padding: 40 is a multiple of 8)
            &f64le(1.0),   // 88: pose.orientation.w
            &[0; 24],      // 96: scale
            &[0; 16],      // 120: color
            &[0; 8],       // 136: lifetime
            &[0],          // 144: frame_locked
            &[0, 0, 0],    // 145: padding to 148
            &[0; 4],       // 148: points count
            &[0; 4],       // 152: colors count
            &[1, 0, 0, 0], // 156: texture_resource length
            &[0],          // 160: NUL, to 161
            &[0, 0, 0],    // 161: padding to 164
            &[0; 8],       // 164: texture.header.stamp
            &[1, 0, 0, 0], // 172: texture.header.frame_id length
            &[0],          // 176: NUL, to 177
            &[0, 0, 0],    // 177: padding to 180
            &[1, 0, 0, 0], // 180: texture.format length
            &[0],          // 184: NUL, to 185
            &[0, 0, 0],    // 185: padding to 188
            &[0; 4],       // 188: texture.data count
            &[0; 4],       // 192: uv_coordinates count
            &[1, 0, 0, 0], // 196: text length
            &[0],          // 200: NUL, to 201
            &[0, 0, 0],    // 201: padding to 204
            &[1, 0, 0, 0], // 204: mesh_resource length
            &[0],          // 208: NUL, to 209
            &[0, 0, 0],    // 209: padding to 212
            &[1, 0, 0, 0], // 212: mesh_file.filename length
            &[0],          // 216: NUL, to 217
            &[0, 0, 0],    // 217: padding to 220
            &[0; 4],       // 220: mesh_file.data count
            &[0],          // 224: mesh_use_embedded_materials; 225 bytes
        ],
    );
}

fn turn(x: f64, y: f64, z: f64, w: f64) -> Quaternion {
    Quaternion { x, y, z, w }
}

#[test]
fn transform() {
    let message = Transform {
        translation: Vector3 {
            x: 0.5,
            y: -0.25,
            z: 2.0,
        },
        rotation: turn(0.0, 0.6, 0.0, 0.8),
    };
    golden(
        &message,
        &[
            &HDR,
            &f64le(0.5), // 0: translation.x
            &f64le(-0.25),
            &f64le(2.0),
            &f64le(0.0), // 24: rotation.x
            &f64le(0.6),
            &f64le(0.0),
            &f64le(0.8), // 48: rotation.w; 56 bytes
        ],
    );
}

#[test]
fn transform_stamped() {
    let message = TransformStamped {
        header: Header {
            stamp: Time { sec: 3, nanosec: 4 },
            frame_id: "world".into(),
        },
        child_frame_id: "wire_tip".into(),
        transform: Transform {
            translation: Vector3 {
                x: 1.0,
                y: 2.0,
                z: 3.0,
            },
            rotation: turn(0.0, 0.0, 0.0, 1.0),
        },
    };
    golden(
        &message,
        &[
            &HDR,
            &[3, 0, 0, 0], // 0: header.stamp.sec
            &[4, 0, 0, 0], // 4: header.stamp.nanosec
            &[6, 0, 0, 0], // 8: frame_id length
            b"world\0",    // 12: "world" NUL, to 18
            &[0, 0],       // 18: padding to 20, uint32 alignment
            &[9, 0, 0, 0], // 20: child_frame_id length
            b"wire_tip\0", // 24: "wire_tip" NUL, to 33
            &[0; 7],       // 33: padding to 40, float64 alignment
            &f64le(1.0),   // 40: transform.translation.x
            &f64le(2.0),
            &f64le(3.0),
            &f64le(0.0), // 64: transform.rotation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(1.0), // 88: transform.rotation.w; 96 bytes
        ],
    );
}

#[test]
fn tf_message() {
    // Two edges: the second starts at body offset 88, so its paddings differ from the first's.
    let edge = |frame: &str, child: &str, x: f64| TransformStamped {
        header: Header {
            stamp: Time { sec: 7, nanosec: 8 },
            frame_id: frame.into(),
        },
        child_frame_id: child.into(),
        transform: Transform {
            translation: Vector3 { x, y: 0.0, z: 0.0 },
            rotation: turn(1.0, 0.0, 0.0, 0.0),
        },
    };
    let message = TFMessage {
        transforms: vec![edge("a", "b", 0.25), edge("wire_base", "t", -4.0)],
    };
    golden(
        &message,
        &[
            &HDR,
            &[2, 0, 0, 0], // 0: transforms count
            &[7, 0, 0, 0], // 4: [0].header.stamp.sec
            &[8, 0, 0, 0], // 8: [0].header.stamp.nanosec
            &[2, 0, 0, 0], // 12: [0].frame_id length
            b"a\0",        // 16: "a" NUL, to 18
            &[0, 0],       // 18: padding to 20
            &[2, 0, 0, 0], // 20: [0].child_frame_id length
            b"b\0",        // 24: "b" NUL, to 26
            &[0; 6],       // 26: padding to 32
            &f64le(0.25),  // 32: [0].transform.translation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(1.0), // 56: [0].transform.rotation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(0.0),
            &[7, 0, 0, 0],  // 88: [1].header.stamp.sec
            &[8, 0, 0, 0],  // 92: [1].header.stamp.nanosec
            &[10, 0, 0, 0], // 96: [1].frame_id length
            b"wire_base\0", // 100: "wire_base" NUL, to 110
            &[0, 0],        // 110: padding to 112
            &[2, 0, 0, 0],  // 112: [1].child_frame_id length
            b"t\0",         // 116: "t" NUL, to 118
            &[0; 2],        // 118: padding to 120
            &f64le(-4.0),   // 120: [1].transform.translation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(1.0), // 144: [1].transform.rotation.x
            &f64le(0.0),
            &f64le(0.0),
            &f64le(0.0), // 168: [1].transform.rotation.w; 176 bytes
        ],
    );
}

#[test]
fn a_big_endian_message_and_middleware_padding_decode() {
    // `00 00`: big-endian; the same Header as `header` above, plus 3 bytes of padding to a
    // multiple of 4 as a middleware may add.
    let bytes = [
        &[0x00, 0x00, 0x00, 0x03][..],
        &[0, 0, 0, 1],
        &[0, 0, 0, 2],
        &[0, 0, 0, 5],
        b"base\0",
        &[0, 0, 0],
    ]
    .concat();
    let header: Header = cdr::decode(&bytes).expect("decodes");
    assert_eq!(header.stamp, Time { sec: 1, nanosec: 2 });
    assert_eq!(header.frame_id, "base");
}

#[test]
fn bad_bytes_are_errors_naming_the_type() {
    let wrench = cdr::encode(&WrenchStamped::default()).expect("encodes");
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (vec![0, 1], "too short"),
        (
            [&[0x00, 0x07, 0, 0][..], &wrench[4..]].concat(),
            "encapsulation",
        ),
        (
            wrench[..wrench.len() - 1].to_vec(),
            "not a geometry_msgs/msg/WrenchStamped",
        ),
        ([&wrench[..], &[0; 8]].concat(), "8 bytes follow"),
    ];
    for (bytes, needle) in cases {
        let error = cdr::decode::<WrenchStamped>(&bytes).expect_err("refused");
        let text = error.to_string();
        assert!(
            text.contains(needle) && text.contains("WrenchStamped"),
            "{text} should mention {needle}"
        );
    }
    // A bool other than 0 or 1.
    let mut marker = cdr::encode(&Marker::default()).expect("encodes");
    let last = marker.len() - 1;
    marker[last] = 2;
    assert!(matches!(
        cdr::decode::<Marker>(&marker),
        Err(CdrError::Decode { .. })
    ));
}

#[test]
fn every_definition_is_rosbag2s_full_text() {
    fn check<M: RosMessage>() {
        let built = full_definition(M::TYPE_NAME).expect("every dependency has a text");
        assert_eq!(M::DEFINITION, built, "{}", M::TYPE_NAME);
    }
    check::<Time>();
    check::<Duration>();
    check::<Header>();
    check::<StringMsg>();
    check::<ColorRGBA>();
    check::<Vector3>();
    check::<Point>();
    check::<Quaternion>();
    check::<Pose>();
    check::<PoseStamped>();
    check::<PoseArray>();
    check::<Wrench>();
    check::<WrenchStamped>();
    check::<Path>();
    check::<CompressedImage>();
    check::<UVCoordinate>();
    check::<MeshFile>();
    check::<Marker>();
    check::<MarkerArray>();
    check::<Transform>();
    check::<TransformStamped>();
    check::<TFMessage>();
    // The layout, spelled out for one type.
    let sep = "=".repeat(80);
    assert_eq!(
        WrenchStamped::DEFINITION,
        format!(
            "std_msgs/Header header\nWrench wrench\n\n{sep}\nMSG: geometry_msgs/Wrench\n\
             Vector3 force\nVector3 torque\n\n{sep}\nMSG: geometry_msgs/Vector3\n\
             float64 x\nfloat64 y\nfloat64 z\n\n{sep}\nMSG: std_msgs/Header\n\
             builtin_interfaces/Time stamp\nstring frame_id\n\n{sep}\n\
             MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
        )
    );
}
