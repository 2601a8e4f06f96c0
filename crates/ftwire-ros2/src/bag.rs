//! ROS 2 bags in MCAP storage, as rosbag2 writes them: profile `ros2`, one schema per message
//! type (encoding `ros2msg`, the type's full definition, [`RosMessage::DEFINITION`]), one
//! channel per topic (message encoding `cdr`, metadata `offered_qos_profiles`: the topic's QoS
//! as rosbag2's YAML, [`offered_qos_profiles`]), each message's bytes as [`crate::cdr::encode`]
//! writes them. Foxglove and `ros2 bag` read such a file.
//!
//! [`BagWriter`] writes one; [`BagReader`] reads any MCAP file's messages in time order, each
//! with its topic, type name, log time and CDR bytes, and decodes them to [`crate::msg`]'s
//! structs. Every error names the file and what is wrong with it.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, ErrorKind};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use ros2_client::QosProfile;
use ros2_client::qos::{Durability, History, Liveliness, Reliability};
use thiserror::Error;

use crate::cdr::{self, CdrError};
use crate::msg::RosMessage;

/// The schema encoding of a ROS 2 `.msg` definition.
pub const SCHEMA_ENCODING: &str = "ros2msg";
/// The message encoding of ROS 2 messages.
pub const MESSAGE_ENCODING: &str = "cdr";
/// The MCAP profile of a ROS 2 bag.
pub const PROFILE: &str = "ros2";
/// The channel metadata key of a topic's QoS profiles.
pub const QOS_KEY: &str = "offered_qos_profiles";

/// A duration rosbag2 writes for an infinite one (`RMW_DURATION_INFINITE`: `i64::MAX` ns as
/// seconds and nanoseconds).
const INFINITE: (u64, u32) = (9_223_372_036, 854_775_807);

/// The QoS a topic's channel carries when none was given: rosbag2's own default (keep the last
/// 10, reliable, volatile, nothing else limited).
pub fn default_qos() -> QosProfile {
    QosProfile::publisher_default().history(History::KeepLast { depth: 10 })
}

/// `profiles` as rosbag2 writes a channel's `offered_qos_profiles`: a YAML list (yaml-cpp's
/// block style, no final newline), one map per profile with `history`, `depth`,
/// `reliability`, `durability`, `deadline`, `lifespan`, `liveliness`,
/// `liveliness_lease_duration` (each duration `sec` and `nsec`; `None`, infinite, as
/// 9223372036 s 854775807 ns) and `avoid_ros_namespace_conventions` (false). With the `jazzy`
/// feature the policies are names (`keep_last`, `reliable`, `transient_local`, `automatic`:
/// rosbag2's metadata version 9), else numbers (rmw's enum values, as Humble's rosbag2 writes
/// them: keep_last 1, keep_all 2; reliable 1, best_effort 2; transient_local 1, volatile 2;
/// automatic 1, manual_by_topic 3). A keep-all history has depth 0.
///
/// # Example
/// ```
/// use ftwire_ros2::bag::{default_qos, offered_qos_profiles};
/// let text = offered_qos_profiles(&[default_qos()]);
/// assert!(text.starts_with("- history: "));
/// assert!(text.contains("\n  depth: 10\n"));
/// assert!(text.ends_with("avoid_ros_namespace_conventions: false"));
/// ```
pub fn offered_qos_profiles(profiles: &[QosProfile]) -> String {
    use std::fmt::Write as _;
    let named = cfg!(feature = "jazzy");
    let policy = |name: &'static str, number: u8| -> String {
        if named {
            name.to_owned()
        } else {
            number.to_string()
        }
    };
    let duration =
        |d: Option<std::time::Duration>| d.map_or(INFINITE, |d| (d.as_secs(), d.subsec_nanos()));
    let mut out = String::new();
    for qos in profiles {
        let (history, depth) = match qos.history {
            History::KeepLast { depth } => (policy("keep_last", 1), depth),
            History::KeepAll => (policy("keep_all", 2), 0),
        };
        let reliability = match qos.reliability {
            Reliability::Reliable { .. } => policy("reliable", 1),
            Reliability::BestEffort => policy("best_effort", 2),
        };
        let durability = match qos.durability {
            Durability::TransientLocal => policy("transient_local", 1),
            Durability::Volatile => policy("volatile", 2),
        };
        let liveliness = match qos.liveliness {
            Liveliness::Automatic => policy("automatic", 1),
            Liveliness::ManualByTopic => policy("manual_by_topic", 3),
        };
        if !out.is_empty() {
            out.push('\n');
        }
        let _ = write!(
            out,
            "- history: {history}\n  depth: {depth}\n  reliability: {reliability}\n  \
             durability: {durability}\n"
        );
        for (key, (sec, nsec)) in [
            ("deadline", duration(qos.deadline)),
            ("lifespan", duration(qos.lifespan)),
        ] {
            let _ = write!(out, "  {key}:\n    sec: {sec}\n    nsec: {nsec}\n");
        }
        let (sec, nsec) = duration(qos.liveliness_lease);
        let _ = write!(
            out,
            "  liveliness: {liveliness}\n  liveliness_lease_duration:\n    sec: {sec}\n    \
             nsec: {nsec}\n  avoid_ros_namespace_conventions: false"
        );
    }
    out
}

/// What went wrong with a bag.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum BagError {
    /// The output file exists and overwriting was not asked for.
    #[error("{} exists: give another file, or allow overwriting it", path.display())]
    Exists {
        /// The file.
        path: PathBuf,
    },
    /// The file could not be opened, read or written.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        message: String,
    },
    /// The file is not a readable MCAP file.
    #[error("{} is not a readable MCAP bag: {message}", path.display())]
    NotMcap {
        /// The file.
        path: PathBuf,
        /// What the MCAP reader found wrong.
        message: String,
    },
    /// A topic was written with two message types.
    #[error(
        "{}: topic {topic} already holds {existing}; it cannot also hold {requested}",
        path.display()
    )]
    TopicType {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
        /// The type already on the topic.
        existing: String,
        /// The type asked for.
        requested: String,
    },
    /// A message could not be encoded or decoded.
    #[error("{}: topic {topic}: {source}", path.display())]
    Cdr {
        /// The file.
        path: PathBuf,
        /// The message's topic.
        topic: String,
        /// What was wrong with the bytes.
        #[source]
        source: CdrError,
    },
    /// A topic's QoS was given after its first message.
    #[error(
        "{}: topic {topic} already has its channel; give its QoS before its first message",
        path.display()
    )]
    QosTooLate {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
    },
    /// A message's topic is not CDR-encoded ROS 2.
    #[error(
        "{}: topic {topic} has message encoding \"{encoding}\"; a ROS 2 bag's messages are \"cdr\"",
        path.display()
    )]
    Encoding {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
        /// Its message encoding.
        encoding: String,
    },
}

/// Writes a ROS 2 bag (MCAP, zstd-compressed chunks, with the summary and indexes that
/// `ros2 bag info` and Foxglove use).
pub struct BagWriter {
    path: PathBuf,
    writer: mcap::Writer<BufWriter<File>>,
    /// Per topic: the channel id, the message type and the next sequence number.
    channels: BTreeMap<String, (u16, &'static str, u32)>,
    /// Per topic: the QoS its channel is to carry (else [`default_qos`]).
    qos: BTreeMap<String, QosProfile>,
}

impl std::fmt::Debug for BagWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BagWriter")
            .field("path", &self.path)
            .field("topics", &self.channels.keys().collect::<Vec<_>>())
            .finish()
    }
}

impl BagWriter {
    /// Creates the bag file at `path`. An existing file is replaced only with `overwrite`.
    ///
    /// # Errors
    /// [`BagError::Exists`], or [`BagError::Io`] when the file cannot be created.
    ///
    /// # Example
    /// ```
    /// use ftwire_ros2::bag::{BagReader, BagWriter};
    /// use ftwire_ros2::msg::StringMsg;
    /// let path = std::env::temp_dir().join(format!("ftwire-doc-{}.mcap", std::process::id()));
    /// let mut bag = BagWriter::create(&path, true)?;
    /// bag.write("/note", 1_000, &StringMsg { data: "rest".into() })?;
    /// bag.finish()?;
    /// let read = BagReader::open(&path)?;
    /// assert_eq!(read.messages().len(), 1);
    /// assert_eq!(read.decode::<StringMsg>(&read.messages()[0])?.data, "rest");
    /// # std::fs::remove_file(&path).ok();
    /// # Ok::<(), ftwire_ros2::bag::BagError>(())
    /// ```
    pub fn create(path: impl AsRef<Path>, overwrite: bool) -> Result<Self, BagError> {
        let path = path.as_ref().to_path_buf();
        let mut options = OpenOptions::new();
        options.write(true);
        if overwrite {
            options.create(true).truncate(true);
        } else {
            options.create_new(true);
        }
        let file = options.open(&path).map_err(|e| {
            if e.kind() == ErrorKind::AlreadyExists {
                BagError::Exists { path: path.clone() }
            } else {
                BagError::Io {
                    path: path.clone(),
                    message: format!("cannot create the bag: {e}"),
                }
            }
        })?;
        let writer = mcap::WriteOptions::new()
            .profile(PROFILE)
            .library(concat!("ftwire-ros2 ", env!("CARGO_PKG_VERSION")))
            .create(BufWriter::new(file))
            .map_err(|e| BagError::Io {
                path: path.clone(),
                message: e.to_string(),
            })?;
        Ok(Self {
            path,
            writer,
            channels: BTreeMap::new(),
            qos: BTreeMap::new(),
        })
    }

    /// Sets the QoS `topic`'s channel carries as `offered_qos_profiles`: the profile the
    /// node published or subscribed with. A topic without one carries [`default_qos`].
    ///
    /// # Errors
    /// [`BagError::QosTooLate`] once the topic has a message.
    pub fn set_qos(&mut self, topic: &str, qos: &QosProfile) -> Result<(), BagError> {
        if self.channels.contains_key(topic) {
            return Err(BagError::QosTooLate {
                path: self.path.clone(),
                topic: topic.to_owned(),
            });
        }
        self.qos.insert(topic.to_owned(), qos.clone());
        Ok(())
    }

    /// Writes `message` on `topic` at `log_time_ns` (ns on the recording's clock; also the
    /// publish time). A topic's first message adds its channel and its type's schema.
    ///
    /// # Errors
    /// [`BagError::TopicType`] when the topic already holds another type; [`BagError::Cdr`]
    /// or [`BagError::Io`] when encoding or writing fails.
    pub fn write<M: RosMessage>(
        &mut self,
        topic: &str,
        log_time_ns: u64,
        message: &M,
    ) -> Result<(), BagError> {
        let data = cdr::encode(message).map_err(|source| BagError::Cdr {
            path: self.path.clone(),
            topic: topic.to_string(),
            source,
        })?;
        let io = |e: mcap::McapError| BagError::Io {
            path: self.path.clone(),
            message: e.to_string(),
        };
        let (channel_id, sequence) = match self.channels.get_mut(topic) {
            Some((id, type_name, sequence)) => {
                if *type_name != M::TYPE_NAME {
                    return Err(BagError::TopicType {
                        path: self.path.clone(),
                        topic: topic.to_string(),
                        existing: (*type_name).to_string(),
                        requested: M::TYPE_NAME.to_string(),
                    });
                }
                *sequence = sequence.wrapping_add(1);
                (*id, *sequence)
            }
            None => {
                let schema = self
                    .writer
                    .add_schema(M::TYPE_NAME, SCHEMA_ENCODING, M::DEFINITION.as_bytes())
                    .map_err(io)?;
                let qos = self.qos.get(topic).cloned().unwrap_or_else(default_qos);
                let metadata = BTreeMap::from([(
                    QOS_KEY.to_owned(),
                    offered_qos_profiles(std::slice::from_ref(&qos)),
                )]);
                let id = self
                    .writer
                    .add_channel(schema, topic, MESSAGE_ENCODING, &metadata)
                    .map_err(io)?;
                self.channels
                    .insert(topic.to_string(), (id, M::TYPE_NAME, 1));
                (id, 1)
            }
        };
        let header = mcap::records::MessageHeader {
            channel_id,
            sequence,
            log_time: log_time_ns,
            publish_time: log_time_ns,
        };
        self.writer
            .write_to_known_channel(&header, &data)
            .map_err(io)
    }

    /// Writes the summary and the footer and closes the file. A bag not finished is not
    /// readable by the tools that need its summary.
    ///
    /// # Errors
    /// [`BagError::Io`] when writing fails.
    pub fn finish(mut self) -> Result<PathBuf, BagError> {
        let io = |message: String| BagError::Io {
            path: self.path.clone(),
            message,
        };
        self.writer.finish().map_err(|e| io(e.to_string()))?;
        use std::io::Write as _;
        self.writer
            .into_inner()
            .flush()
            .map_err(|e| io(e.to_string()))?;
        Ok(self.path)
    }
}

/// A topic of a bag: its name, message type (the schema's name, such as
/// `geometry_msgs/msg/WrenchStamped`; empty when the channel has no schema) and message
/// encoding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topic {
    /// The topic's name.
    pub name: String,
    /// The ROS 2 type.
    pub type_name: String,
    /// The message encoding (`cdr` in a ROS 2 bag).
    pub encoding: String,
    /// How many messages the bag holds on it.
    pub count: usize,
    /// The channel's `offered_qos_profiles` ([`offered_qos_profiles`]; empty when it has none).
    pub offered_qos_profiles: String,
}

/// One message of a bag.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BagMessage {
    /// Its topic (shared by the topic's messages).
    pub topic: Arc<Topic>,
    /// The log time \[ns\] (when the recorder received it).
    pub log_time: u64,
    /// The serialised message (CDR, with its encapsulation header).
    pub data: Vec<u8>,
}

/// A bag read whole: its topics and its messages in log-time order (messages with equal log
/// times in file order).
#[derive(Debug, Clone)]
pub struct BagReader {
    path: PathBuf,
    topics: Vec<Arc<Topic>>,
    messages: Vec<BagMessage>,
}

impl BagReader {
    /// Reads the bag at `path`.
    ///
    /// # Errors
    /// [`BagError::Io`] when the file cannot be read, [`BagError::NotMcap`] when it is not a
    /// valid MCAP file (a bad magic number, a truncated record, a bad checksum), naming the
    /// file.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, BagError> {
        let path = path.as_ref().to_path_buf();
        let bytes = std::fs::read(&path).map_err(|e| BagError::Io {
            path: path.clone(),
            message: format!("cannot read the bag: {e}"),
        })?;
        let not_mcap = |e: mcap::McapError| BagError::NotMcap {
            path: path.clone(),
            message: e.to_string(),
        };
        let mut by_channel: BTreeMap<(u16, String), usize> = BTreeMap::new();
        let mut topics: Vec<Topic> = Vec::new();
        let mut raw: Vec<(usize, u64, Vec<u8>)> = Vec::new();
        for message in mcap::MessageStream::new(&bytes).map_err(not_mcap)? {
            let message = message.map_err(not_mcap)?;
            let channel = &message.channel;
            let key = (channel.id, channel.topic.clone());
            let index = match by_channel.get(&key) {
                Some(&i) => i,
                None => {
                    topics.push(Topic {
                        name: channel.topic.clone(),
                        type_name: channel
                            .schema
                            .as_ref()
                            .map(|s| s.name.clone())
                            .unwrap_or_default(),
                        encoding: channel.message_encoding.clone(),
                        count: 0,
                        offered_qos_profiles: channel
                            .metadata
                            .get(QOS_KEY)
                            .cloned()
                            .unwrap_or_default(),
                    });
                    by_channel.insert(key, topics.len() - 1);
                    topics.len() - 1
                }
            };
            if let Some(topic) = topics.get_mut(index) {
                topic.count += 1;
            }
            raw.push((index, message.log_time, message.data.into_owned()));
        }
        raw.sort_by_key(|(_, time, _)| *time);
        let topics: Vec<Arc<Topic>> = topics.into_iter().map(Arc::new).collect();
        let messages = raw
            .into_iter()
            .filter_map(|(index, log_time, data)| {
                topics.get(index).map(|topic| BagMessage {
                    topic: Arc::clone(topic),
                    log_time,
                    data,
                })
            })
            .collect();
        Ok(Self {
            path,
            topics,
            messages,
        })
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The topics that hold messages, in the order of their first message in the file.
    pub fn topics(&self) -> &[Arc<Topic>] {
        &self.topics
    }

    /// The topic called `name`, if the bag has messages on it.
    pub fn topic(&self, name: &str) -> Option<&Topic> {
        self.topics.iter().find(|t| t.name == name).map(|t| &**t)
    }

    /// Every message, in log-time order.
    pub fn messages(&self) -> &[BagMessage] {
        &self.messages
    }

    /// The topics as `name (type)`, comma separated, for messages naming what a bag has.
    pub fn topic_list(&self) -> String {
        if self.topics.is_empty() {
            return "none".into();
        }
        self.topics
            .iter()
            .map(|t| format!("{} ({})", t.name, t.type_name))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Decodes one of this bag's messages as `M`.
    ///
    /// # Errors
    /// [`BagError::Encoding`] when the message's topic is not CDR, [`BagError::Cdr`] when
    /// its bytes are not an `M`.
    pub fn decode<M: RosMessage>(&self, message: &BagMessage) -> Result<M, BagError> {
        if message.topic.encoding != MESSAGE_ENCODING {
            return Err(BagError::Encoding {
                path: self.path.clone(),
                topic: message.topic.name.clone(),
                encoding: message.topic.encoding.clone(),
            });
        }
        cdr::decode(&message.data).map_err(|source| BagError::Cdr {
            path: self.path.clone(),
            topic: message.topic.name.clone(),
            source,
        })
    }
}
