//! Sessions: a session's file checked line by line, the folder's sessions, their verification
//! and their routes.

pub mod registry;
pub mod room_scene;
pub mod routes;
pub mod session;
pub mod verify;
