//! ROS 2 bags in MCAP storage, as rosbag2 writes them: profile `ros2`, one schema per message
//! type (encoding `ros2msg`, the type's full definition, [`RosMessage::DEFINITION`]), one
//! channel per topic (message encoding `cdr`), each message's bytes as [`crate::cdr::encode`]
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

use thiserror::Error;

use crate::cdr::{self, CdrError};
use crate::msg::RosMessage;

/// The schema encoding of a ROS 2 `.msg` definition.
pub const SCHEMA_ENCODING: &str = "ros2msg";
/// The message encoding of ROS 2 messages.
pub const MESSAGE_ENCODING: &str = "cdr";
/// The MCAP profile of a ROS 2 bag.
pub const PROFILE: &str = "ros2";

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
        })
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
                let id = self
                    .writer
                    .add_channel(schema, topic, MESSAGE_ENCODING, &BTreeMap::new())
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
