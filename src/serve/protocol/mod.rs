//! A study protocol run by the server: participants, their routes, the dashboard's live views
//! and the two pages.

pub mod live;
pub mod pages;
pub mod participants;
pub mod routes;
