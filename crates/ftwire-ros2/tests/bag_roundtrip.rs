//! A bag written by `BagWriter` reads back with the same messages, in time order, with the
//! channels and schemas rosbag2 writes; the writer never replaces a file unless told; a reader
//! error names the file.

use std::path::PathBuf;

use ftwire_ros2::bag::{BagError, BagReader, BagWriter};
use ftwire_ros2::msg::*;

/// A fresh path in the temporary folder, removed first.
fn temp(name: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("ftwire-ros2-{}-{name}", std::process::id()));
    std::fs::remove_file(&path).ok();
    path
}

fn stamped(sec: i32, frame: &str) -> Header {
    Header {
        stamp: Time {
            sec,
            nanosec: 250_000_000,
        },
        frame_id: frame.into(),
    }
}

#[test]
fn messages_read_back_the_same_in_time_order() {
    let path = temp("roundtrip.mcap");
    let wrench = WrenchStamped {
        header: stamped(3, "ft_sensor"),
        wrench: Wrench {
            force: Vector3 {
                x: 1.5,
                y: -0.25,
                z: 9.0,
            },
            torque: Vector3 {
                x: 0.01,
                y: 0.02,
                z: -0.03,
            },
        },
    };
    let tip = PoseStamped {
        header: stamped(2, "base_clamp"),
        pose: Pose {
            position: Point {
                x: 0.6,
                y: 0.05,
                z: 0.0,
            },
            orientation: Quaternion {
                x: 0.0,
                y: 0.0,
                z: 0.14943813247359922,
                w: 0.9887710779360422,
            },
        },
    };
    let markers = PoseArray {
        header: stamped(1, "base_clamp"),
        poses: vec![Pose::default(), Pose::default()],
    };
    let path_msg = Path {
        header: stamped(1, "base_clamp"),
        poses: vec![tip.clone(), tip.clone()],
    };
    let marker = Marker {
        header: stamped(1, "base_clamp"),
        ns: "wire".into(),
        kind: Marker::LINE_STRIP,
        points: vec![Point::default(), tip.pose.position],
        ..Marker::default()
    };
    let note = StringMsg {
        data: "rest 1".into(),
    };
    let mut bag = BagWriter::create(&path, false).expect("creates");
    // Written out of time order: the reader sorts by log time.
    bag.write("/ft", 3_000, &wrench).expect("writes");
    bag.write("/tip", 2_000, &tip).expect("writes");
    bag.write("/markers", 1_000, &markers).expect("writes");
    bag.write("/shape", 4_000, &path_msg).expect("writes");
    bag.write("/shape_marker", 5_000, &marker).expect("writes");
    bag.write("/note", 6_000, &note).expect("writes");
    bag.write("/ft", 7_000, &wrench).expect("writes");
    match bag.write("/ft", 8_000, &tip) {
        Err(BagError::TopicType { topic, .. }) => assert_eq!(topic, "/ft"),
        other => panic!("a second type on a topic must be refused: {other:?}"),
    }
    bag.finish().expect("finishes");

    let read = BagReader::open(&path).expect("reads");
    let times: Vec<u64> = read.messages().iter().map(|m| m.log_time).collect();
    assert_eq!(times, [1_000, 2_000, 3_000, 4_000, 5_000, 6_000, 7_000]);
    let names: Vec<(&str, &str)> = read
        .messages()
        .iter()
        .map(|m| (m.topic.name.as_str(), m.topic.type_name.as_str()))
        .collect();
    assert_eq!(
        names,
        [
            ("/markers", "geometry_msgs/msg/PoseArray"),
            ("/tip", "geometry_msgs/msg/PoseStamped"),
            ("/ft", "geometry_msgs/msg/WrenchStamped"),
            ("/shape", "nav_msgs/msg/Path"),
            ("/shape_marker", "visualization_msgs/msg/Marker"),
            ("/note", "std_msgs/msg/String"),
            ("/ft", "geometry_msgs/msg/WrenchStamped"),
        ]
    );
    let m = read.messages();
    assert_eq!(read.decode::<PoseArray>(&m[0]).expect("decodes"), markers);
    assert_eq!(read.decode::<PoseStamped>(&m[1]).expect("decodes"), tip);
    assert_eq!(
        read.decode::<WrenchStamped>(&m[2]).expect("decodes"),
        wrench
    );
    assert_eq!(read.decode::<Path>(&m[3]).expect("decodes"), path_msg);
    assert_eq!(read.decode::<Marker>(&m[4]).expect("decodes"), marker);
    assert_eq!(read.decode::<StringMsg>(&m[5]).expect("decodes"), note);
    assert_eq!(read.topic("/ft").map(|t| t.count), Some(2));
    // The bytes in the bag are exactly the CDR encoding.
    assert_eq!(
        m[2].data,
        ftwire_ros2::cdr::encode(&wrench).expect("encodes")
    );
    // Decoding as the wrong type is an error naming the file and topic.
    let error = read.decode::<Time>(&m[2]).expect_err("not a Time");
    assert!(error.to_string().contains("/ft"), "{error}");

    // What rosbag2 writes: profile ros2, schemas ros2msg with the full definition, channels
    // cdr, a summary with statistics.
    let bytes = std::fs::read(&path).expect("reads");
    let summary = mcap::Summary::read(&bytes)
        .expect("a summary")
        .expect("a summary section");
    let stats = summary.stats.as_ref().expect("statistics");
    assert_eq!(stats.message_count, 7);
    for channel in summary.channels.values() {
        assert_eq!(channel.message_encoding, "cdr", "{}", channel.topic);
        let schema = channel.schema.as_ref().expect("a schema");
        assert_eq!(schema.encoding, "ros2msg");
        if schema.name == WrenchStamped::TYPE_NAME {
            assert_eq!(&*schema.data, WrenchStamped::DEFINITION.as_bytes());
        }
    }
    let header = mcap::read::LinearReader::new(&bytes)
        .expect("reads")
        .find_map(|record| match record {
            Ok(mcap::records::Record::Header(h)) => Some(h),
            _ => None,
        })
        .expect("a header record");
    assert_eq!(header.profile, "ros2");
    std::fs::remove_file(&path).ok();
}

#[test]
fn an_existing_file_is_replaced_only_when_told() {
    let path = temp("exists.mcap");
    std::fs::write(&path, b"keep me").expect("writes");
    match BagWriter::create(&path, false) {
        Err(BagError::Exists { path: p }) => assert_eq!(p, path),
        other => panic!("expected Exists, got {other:?}"),
    }
    assert_eq!(std::fs::read(&path).expect("reads"), b"keep me");
    let bag = BagWriter::create(&path, true).expect("replaces");
    bag.finish().expect("finishes");
    assert!(BagReader::open(&path).expect("reads").messages().is_empty());
    std::fs::remove_file(&path).ok();
}

#[test]
fn a_reader_error_names_the_file_and_what_is_wrong() {
    let missing = temp("missing.mcap");
    let error = BagReader::open(&missing).expect_err("no file");
    assert!(
        error.to_string().contains(&missing.display().to_string())
            && error.to_string().contains("cannot read"),
        "{error}"
    );

    let garbage = temp("garbage.mcap");
    std::fs::write(&garbage, b"this is not a bag at all").expect("writes");
    let error = BagReader::open(&garbage).expect_err("not MCAP");
    let text = error.to_string();
    assert!(
        text.contains(&garbage.display().to_string()) && text.contains("not a readable MCAP"),
        "{text}"
    );

    // A bag cut short in its data.
    let cut = temp("cut.mcap");
    let mut bag = BagWriter::create(&cut, false).expect("creates");
    for i in 0..200 {
        bag.write(
            "/note",
            i,
            &StringMsg {
                data: "x".repeat(100),
            },
        )
        .expect("writes");
    }
    bag.finish().expect("finishes");
    let bytes = std::fs::read(&cut).expect("reads");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("writes");
    let error = BagReader::open(&cut).expect_err("truncated");
    assert!(
        error.to_string().contains(&cut.display().to_string()),
        "{error}"
    );
    for path in [garbage, cut] {
        std::fs::remove_file(path).ok();
    }
}
