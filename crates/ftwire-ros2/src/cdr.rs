//! CDR, the bytes of a ROS 2 message on the wire and in a bag.
//!
//! A serialised message is a 4-byte encapsulation header, then the body in plain CDR (XCDR1,
//! the representation ROS 2's middlewares use): the fields in declaration order with no names;
//! each primitive aligned to its own size (`float64` to 8, `int32`/`float32` to 4) counted from
//! the start of the body, not of the header; a string as a `uint32` length that counts a
//! terminating NUL, the bytes and the NUL; a sequence as a `uint32` count and its elements; a
//! `bool` one byte. [`encode`] writes the little-endian header `00 01 00 00` (what ROS 2 sends
//! from x86 and ARM). [`decode`] reads either byte order, and accepts up to 3 bytes after the
//! body: middlewares pad a message to a multiple of 4 bytes.

use byteorder::{BigEndian, LittleEndian};
use thiserror::Error;

use crate::msg::RosMessage;

/// The encapsulation header of plain CDR, little-endian (`CDR_LE`): representation id
/// `00 01`, options `00 00`.
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// The encapsulation header of plain CDR, big-endian (`CDR_BE`), as [`decode`] also reads it.
pub const CDR_BE: [u8; 4] = [0x00, 0x00, 0x00, 0x00];

/// Why a message could not be encoded or decoded.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum CdrError {
    /// The message could not be written as CDR.
    #[error("cannot encode a {type_name} as CDR: {message}")]
    Encode {
        /// The message's ROS 2 type.
        type_name: &'static str,
        /// What went wrong.
        message: String,
    },
    /// Fewer bytes than the encapsulation header.
    #[error(
        "a {type_name} of {len} bytes is too short: a CDR message starts with a 4-byte encapsulation header"
    )]
    TooShort {
        /// The expected ROS 2 type.
        type_name: &'static str,
        /// The number of bytes given.
        len: usize,
    },
    /// An encapsulation other than plain CDR.
    #[error(
        "a {type_name} with encapsulation {found:02X?} cannot be read: plain CDR (00 01 little-endian or 00 00 big-endian) is allowed"
    )]
    Encapsulation {
        /// The expected ROS 2 type.
        type_name: &'static str,
        /// The first two bytes.
        found: [u8; 2],
    },
    /// The body does not hold a message of the type.
    #[error("the bytes are not a {type_name}: {message}")]
    Decode {
        /// The expected ROS 2 type.
        type_name: &'static str,
        /// What went wrong.
        message: String,
    },
    /// More bytes after the message than the padding a middleware adds.
    #[error(
        "{extra} bytes follow the {type_name}: at most 3 bytes of padding are allowed (is it another type?)"
    )]
    Trailing {
        /// The expected ROS 2 type.
        type_name: &'static str,
        /// The number of bytes after the body.
        extra: usize,
    },
}

/// The message as ROS 2 serialises it: [`CDR_LE`], then the body.
///
/// # Errors
/// [`CdrError::Encode`] if the serialiser refuses a value (it does not for the types of
/// [`crate::msg`]).
///
/// # Example
/// ```
/// use ftwire_ros2::{cdr, msg::Vector3};
/// let bytes = cdr::encode(&Vector3 { x: 1.0, y: 0.0, z: 0.0 })?;
/// assert_eq!(bytes.len(), 4 + 24);
/// assert_eq!(&bytes[..4], &cdr::CDR_LE);
/// assert_eq!(&bytes[4..12], &1.0f64.to_le_bytes());
/// # Ok::<(), cdr::CdrError>(())
/// ```
pub fn encode<M: RosMessage>(message: &M) -> Result<Vec<u8>, CdrError> {
    let mut bytes = Vec::with_capacity(64);
    bytes.extend_from_slice(&CDR_LE);
    // The body goes through its own serialiser, so that alignment counts from the body's start.
    let body = cdr_encoding::to_vec::<M, LittleEndian>(message).map_err(|e| CdrError::Encode {
        type_name: M::TYPE_NAME,
        message: e.to_string(),
    })?;
    bytes.extend_from_slice(&body);
    Ok(bytes)
}

/// Reads a message written by [`encode`] or by ROS 2 (either byte order; up to 3 bytes of
/// padding after the body).
///
/// # Errors
/// [`CdrError::TooShort`], [`CdrError::Encapsulation`], [`CdrError::Decode`] (the body ends
/// early or holds an invalid value, such as a `bool` other than 0 or 1 or a string that is not
/// UTF-8) or [`CdrError::Trailing`], each naming the expected type.
///
/// # Example
/// ```
/// use ftwire_ros2::{cdr, msg::StringMsg};
/// let message = StringMsg { data: "clamp".into() };
/// assert_eq!(cdr::decode::<StringMsg>(&cdr::encode(&message)?)?, message);
/// assert!(cdr::decode::<StringMsg>(&[0, 1, 0]).is_err());
/// # Ok::<(), cdr::CdrError>(())
/// ```
pub fn decode<M: RosMessage>(bytes: &[u8]) -> Result<M, CdrError> {
    let type_name = M::TYPE_NAME;
    let (header, body) = match bytes.split_first_chunk::<4>() {
        Some((header, body)) => (header, body),
        None => {
            return Err(CdrError::TooShort {
                type_name,
                len: bytes.len(),
            });
        }
    };
    let decoded = match [header[0], header[1]] {
        [0x00, 0x01] => cdr_encoding::from_bytes::<M, LittleEndian>(body),
        [0x00, 0x00] => cdr_encoding::from_bytes::<M, BigEndian>(body),
        found => return Err(CdrError::Encapsulation { type_name, found }),
    };
    let (message, used) = decoded.map_err(|e| CdrError::Decode {
        type_name,
        message: e.to_string(),
    })?;
    let extra = body.len().saturating_sub(used);
    if extra > 3 {
        return Err(CdrError::Trailing { type_name, extra });
    }
    Ok(message)
}
