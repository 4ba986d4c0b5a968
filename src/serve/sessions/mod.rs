//! Sessions: recordings streamed line by line into a folder. `session.rs` one session's file,
//! every line checked by the replay crate's rules before it is written; `registry.rs` the
//! folder's sessions and `sessions.json`; `states.rs` the states a session and its verification
//! are in; `live.rs` and `live_replay.rs` every session's file replayed and verified by a worker
//! as its lines are acknowledged; `verify.rs` a verification's fields and the re-simulation of a
//! whole file; `room_scene.rs` a scene a
//! client built, kept beside the recordings; `service.rs` the sessions as requests reach them
//! (a reader, a writer and its lease); `routes.rs` the routes under `/api/sessions`; `jobs.rs`
//! what happens besides requests (ending, verifying, abandoning, flushing at the stop);
//! `error.rs` why a session was refused, one enum.
//!
//! It knows HTTP only through the layer beneath (`serve/http/`: the body reader, the router,
//! responses). It does not know protocols, participants, the token, TLS or the served files.

pub mod error;
pub mod jobs;
pub mod live;
pub mod live_replay;
pub mod registry;
pub mod room_scene;
pub mod routes;
pub mod service;
pub mod session;
pub mod states;
pub mod verify;
