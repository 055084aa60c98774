//! What the CAVE's master and render nodes say to each other, and the link that carries it:
//! serde messages (JSON) in length-delimited frames (tokio-util's `LengthDelimitedCodec`, used
//! synchronously on a blocking `TcpStream`) with a deadline on every read.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use bytes::{Bytes, BytesMut};
use serde::{Deserialize, Serialize};
use tokio_util::codec::{Decoder, Encoder, LengthDelimitedCodec};

use crate::render::FrameOptions;
use crate::view::cave::EyeChoice;

/// Bumped whenever a message changes shape: a node and a master of different protocols refuse
/// each other at the handshake.
pub const PROTOCOL: u32 = 1;

/// The build both ends must share: the same version, protocol and shaders (a digest of every
/// shader's SPIR-V), so that every node draws the same pixels.
pub fn build() -> String {
    let shaders = crate::shaders::ALL
        .iter()
        .fold(crate::digest::FNV_OFFSET, |hash, spirv| {
            crate::digest::fnv1a(spirv.iter().copied(), hash)
        });
    format!(
        "vkgi {} protocol {PROTOCOL} shaders {shaders:016x}",
        env!("CARGO_PKG_VERSION")
    )
}

/// The longest message either end accepts (a frame's updates are a few hundred bytes).
const MAX_MESSAGE: usize = 1 << 20;
/// The longest a message may take to leave (the peer's receive buffer is full).
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);

/// A node to the master.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub enum NodeMessage {
    /// The first message: who the node is and what it renders.
    Hello {
        build: String,
        wall: String,
        eye: EyeChoice,
        /// The scene's content digest (see `Scene::digest`) and name.
        scene: String,
        scene_name: String,
    },
    /// The node set up its device, frame and GI method: it can render.
    Ready,
    /// The node holds the parameters of `version` (sent at once, before rendering: the master's
    /// parameter-sync latency is the round trip to the last of these).
    Applied { frame: u64, version: u64 },
    /// The node finished frame `frame` on its GPU.
    Finished {
        frame: u64,
        version: u64,
        /// A digest of the light state the GI method carries to the next frame (None: the
        /// method carries none).
        lattice: Option<u64>,
        /// How long the node waited for this frame after finishing the previous one (the
        /// frame lock's wait), in milliseconds.
        lock_wait_ms: f64,
        /// The node's GPU work for the frame, submit to finish, in milliseconds.
        render_ms: f64,
    },
}

/// The master to a node.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub enum MasterMessage {
    /// The node was accepted: the method and its settings every node renders with.
    Welcome(RunSettings),
    /// The node cannot join (another build or scene, a wall already taken), in one line.
    Refused { reason: String },
    /// Render frame `frame` with the parameters of `version`: `updates` take the node from
    /// `since` (the version of its previous frame) to `version`. Also the frame lock's release:
    /// every node finished the frame before.
    Frame {
        frame: u64,
        since: u64,
        version: u64,
        updates: Vec<Update>,
        /// The last frame's sync figures, for the node's overlay.
        sync_ms: f64,
        lock_wait_ms: f64,
    },
    /// The run is over (all frames done, or the master stops): save and exit.
    Stop { reason: String },
}

/// What every node of a run draws with, sent in the welcome.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RunSettings {
    pub method: String,
    pub settings: Vec<(String, String)>,
    /// The CAVE's wall size as a fraction of the scene's diagonal.
    pub cave_size: f32,
    /// The distance between the eyes, as a fraction of the wall size.
    pub eye_separation: f32,
    /// Walls are drawn with their outer pixel centres on their edges (`Wall::edge_centred`).
    pub edge_pixels: bool,
    /// What every wall is drawn with (exposure, shadow maps, indirect only, parts); each node
    /// keeps its own size.
    pub frame: FrameOptions,
    /// Samples per emissive triangle the rasteriser's lights take.
    pub area_samples: u32,
    /// How long the master may wait for the others after this node is ready: the node waits
    /// that much longer for its first frame.
    pub join_timeout_s: f64,
}

impl RunSettings {
    /// Refuse values no master of this build sends (the node then stops with one line).
    pub fn check(&self) -> anyhow::Result<()> {
        crate::view::cave::check_size(self.cave_size)
            .map_err(|e| anyhow::anyhow!("the master sent {e}"))?;
        let separation = self.eye_separation;
        if !(separation.is_finite() && (0.0..=1.0).contains(&separation)) {
            anyhow::bail!("the master sent an eye separation of {separation}");
        }
        let join = self.join_timeout_s;
        if !(join.is_finite() && (0.0..=86_400.0).contains(&join)) {
            anyhow::bail!("the master sent a join timeout of {join} s");
        }
        Ok(())
    }

    pub fn join_timeout(&self) -> Duration {
        Duration::from_secs_f64(self.join_timeout_s)
    }
}

/// One parameter change. Vectors travel as the bits of their floats, so every node gets
/// exactly the value the master computed (a decimal round trip could differ in the last bit).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Update {
    /// The tracked head, relative to the CAVE's centre in half-sizes (right, up, back).
    Head(#[serde(with = "vector_bits")] [f32; 3]),
    /// The scene's first light moves to this world position.
    Light(#[serde(with = "vector_bits")] [f32; 3]),
}

/// An `[f32; 3]` as the `u32` bits of its components.
mod vector_bits {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(v: &[f32; 3], s: S) -> Result<S::Ok, S::Error> {
        v.map(f32::to_bits).serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
        Ok(<[u32; 3]>::deserialize(d)?.map(f32::from_bits))
    }
}

/// Why a message did not arrive.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    #[error("no message within {0:.1} s")]
    Timeout(f64),
    #[error("the connection closed")]
    Closed,
    #[error("a malformed message: {0}")]
    Malformed(String),
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// One end of a master–node connection.
pub struct Link {
    stream: TcpStream,
    codec: LengthDelimitedCodec,
    received: BytesMut,
}

impl Link {
    pub fn new(stream: TcpStream) -> std::io::Result<Link> {
        stream.set_nodelay(true)?;
        // A peer that stops reading must not block a sender forever.
        stream.set_write_timeout(Some(WRITE_TIMEOUT))?;
        Ok(Link {
            stream,
            codec: LengthDelimitedCodec::builder()
                .max_frame_length(MAX_MESSAGE)
                .new_codec(),
            received: BytesMut::new(),
        })
    }

    pub fn send<T: Serialize>(&mut self, message: &T) -> Result<(), LinkError> {
        let body = serde_json::to_vec(message).map_err(|e| LinkError::Malformed(e.to_string()))?;
        let mut framed = BytesMut::new();
        self.codec
            .encode(Bytes::from(body), &mut framed)
            .map_err(|e| LinkError::Malformed(e.to_string()))?;
        match self.stream.write_all(&framed) {
            Ok(()) => Ok(()),
            Err(e) if is_disconnect(e.kind()) => Err(LinkError::Closed),
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                Err(LinkError::Timeout(WRITE_TIMEOUT.as_secs_f64()))
            }
            Err(e) => Err(e.into()),
        }
    }

    /// The next message, waiting at most `timeout`.
    pub fn receive<T: for<'de> Deserialize<'de>>(
        &mut self,
        timeout: Duration,
    ) -> Result<T, LinkError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(frame) = self
                .codec
                .decode(&mut self.received)
                .map_err(|e| LinkError::Malformed(e.to_string()))?
            {
                return serde_json::from_slice(&frame)
                    .map_err(|e| LinkError::Malformed(e.to_string()));
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(LinkError::Timeout(timeout.as_secs_f64()));
            }
            self.stream.set_read_timeout(Some(left))?;
            let mut chunk = [0u8; 4096];
            match self.stream.read(&mut chunk) {
                Ok(0) => return Err(LinkError::Closed),
                Ok(n) => self.received.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) if is_disconnect(e.kind()) => return Err(LinkError::Closed),
                Err(e) => return Err(e.into()),
            }
        }
    }
}

fn is_disconnect(kind: ErrorKind) -> bool {
    matches!(
        kind,
        ErrorKind::ConnectionReset | ErrorKind::ConnectionAborted | ErrorKind::BrokenPipe
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    fn pair() -> (Link, Link) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (server, _) = listener.accept().unwrap();
        (Link::new(server).unwrap(), Link::new(client).unwrap())
    }

    #[test]
    fn messages_cross_a_connection_whole_and_in_order() {
        let (mut master, mut node) = pair();
        let frames: Vec<MasterMessage> = (0..50)
            .map(|f| MasterMessage::Frame {
                frame: f,
                since: f,
                version: f + 1,
                updates: vec![
                    Update::Head([f as f32, 0.5, -0.25]),
                    Update::Light([0.1 + f32::EPSILON, f32::MIN_POSITIVE, -1e30]),
                ],
                sync_ms: 0.25,
                lock_wait_ms: 1.5,
            })
            .collect();
        for message in &frames {
            master.send(message).unwrap();
        }
        for expected in &frames {
            let got: MasterMessage = node.receive(Duration::from_secs(5)).unwrap();
            assert_eq!(&got, expected);
        }
    }

    #[test]
    fn a_silent_peer_times_out_and_a_closed_one_is_reported() {
        let (master, mut node) = pair();
        let silent = node.receive::<MasterMessage>(Duration::from_millis(50));
        assert!(matches!(silent, Err(LinkError::Timeout(_))), "{silent:?}");
        drop(master);
        let closed = node.receive::<MasterMessage>(Duration::from_secs(5));
        assert!(matches!(closed, Err(LinkError::Closed)), "{closed:?}");
    }

    #[test]
    fn garbage_and_oversized_frames_are_malformed_not_a_panic() {
        let (master, mut node) = pair();
        let mut raw = master.stream.try_clone().unwrap();
        raw.write_all(&[0, 0, 0, 3, b'x', b'y', b'z']).unwrap();
        let garbage = node.receive::<MasterMessage>(Duration::from_secs(5));
        assert!(
            matches!(garbage, Err(LinkError::Malformed(_))),
            "{garbage:?}"
        );
        let (master, mut node) = pair();
        let mut raw = master.stream.try_clone().unwrap();
        raw.write_all(&[0x7f, 0xff, 0xff, 0xff]).unwrap();
        let huge = node.receive::<MasterMessage>(Duration::from_secs(5));
        assert!(matches!(huge, Err(LinkError::Malformed(_))), "{huge:?}");
    }
}
