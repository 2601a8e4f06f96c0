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

/// The `key: value` pairs of a YAML list of maps as rosbag2 writes `offered_qos_profiles`
/// (block style, two spaces per level), one map per `- ` item; a nested map's keys are joined
/// with a dot (`deadline.sec`). Panics on a line that is not of that form.
fn qos_items(text: &str) -> Vec<std::collections::BTreeMap<String, String>> {
    let mut items = Vec::new();
    let mut parent = String::new();
    for line in text.lines() {
        let (indent, rest) = match line.strip_prefix("- ") {
            Some(rest) => {
                items.push(std::collections::BTreeMap::new());
                (2, rest)
            }
            None => {
                let trimmed = line.trim_start_matches(' ');
                (line.len() - trimmed.len(), trimmed)
            }
        };
        let (key, value) = rest
            .split_once(':')
            .unwrap_or_else(|| panic!("not `key: value`: {line:?}"));
        let value = value.trim();
        let item = items.last_mut().expect("a line before the first item");
        match indent {
            2 if value.is_empty() => parent = key.to_owned(),
            2 => {
                item.insert(key.to_owned(), value.to_owned());
            }
            4 => {
                item.insert(format!("{parent}.{key}"), value.to_owned());
            }
            _ => panic!("unexpected indentation: {line:?}"),
        }
    }
    items
}

#[test]
fn every_channel_carries_its_qos_as_rosbag2_writes_it() {
    use ftwire_ros2::bag::{default_qos, offered_qos_profiles};
    use ros2_client::QosProfile;
    use ros2_client::qos::{Durability, History, WhenFull};

    let path = temp("qos.mcap");
    let latched = QosProfile::publisher_default()
        .reliability_reliable(WhenFull::DEFAULT)
        .durability(Durability::TransientLocal)
        .history(History::KeepAll);
    let stream = QosProfile::subscription_default().history(History::KeepLast { depth: 1000 });
    let mut bag = BagWriter::create(&path, false).expect("creates");
    bag.set_qos("/tf_static", &latched)
        .expect("before the topic");
    bag.set_qos("/ft", &stream).expect("before the topic");
    bag.write("/tf_static", 1, &TFMessage::default())
        .expect("writes");
    bag.write("/ft", 2, &WrenchStamped::default())
        .expect("writes");
    bag.write("/note", 3, &StringMsg::default())
        .expect("writes");
    assert!(matches!(
        bag.set_qos("/ft", &latched),
        Err(BagError::QosTooLate { .. })
    ));
    bag.finish().expect("finishes");

    let read = BagReader::open(&path).expect("reads");
    let named = cfg!(feature = "jazzy");
    let name = |jazzy: &str, humble: &str| if named { jazzy } else { humble }.to_owned();
    for (topic, depth, reliability, durability) in [
        (
            "/tf_static",
            "0",
            name("reliable", "1"),
            name("transient_local", "1"),
        ),
        (
            "/ft",
            "1000",
            name("best_effort", "2"),
            name("volatile", "2"),
        ),
        ("/note", "10", name("reliable", "1"), name("volatile", "2")),
    ] {
        let text = &read.topic(topic).expect("the topic").offered_qos_profiles;
        let items = qos_items(text);
        assert_eq!(items.len(), 1, "{topic}: {text}");
        let item = &items[0];
        assert_eq!(item["depth"], depth, "{topic}: {text}");
        assert_eq!(item["reliability"], reliability, "{topic}: {text}");
        assert_eq!(item["durability"], durability, "{topic}: {text}");
        assert_eq!(item["liveliness"], name("automatic", "1"), "{topic}");
        for key in ["deadline", "lifespan", "liveliness_lease_duration"] {
            assert_eq!(item[&format!("{key}.sec")], "9223372036", "{topic}: {key}");
            assert_eq!(item[&format!("{key}.nsec")], "854775807", "{topic}: {key}");
        }
        assert_eq!(item["avoid_ros_namespace_conventions"], "false");
        assert_eq!(item.len(), 12, "every key rosbag2 writes, once: {text}");
    }
    // The layout, spelled out for the default.
    let h = name("keep_last", "1");
    let (r, d, l) = (
        name("reliable", "1"),
        name("volatile", "2"),
        name("automatic", "1"),
    );
    let infinite = "    sec: 9223372036\n    nsec: 854775807\n";
    assert_eq!(
        offered_qos_profiles(&[default_qos()]),
        format!(
            "- history: {h}\n  depth: 10\n  reliability: {r}\n  durability: {d}\n  deadline:\n\
             {infinite}  lifespan:\n{infinite}  liveliness: {l}\n  liveliness_lease_duration:\n\
             {infinite}  avoid_ros_namespace_conventions: false"
        )
    );
    std::fs::remove_file(&path).ok();
}
