//! One self-contained HTML page per run (`--html FILE` on `profile`, `profile-app` and
//! `bench`), as Arm's Performance Advisor gives one: the page (page.rs), its charts
//! (charts.rs), and what each command puts on it (from_app.rs, from_profile.rs).

pub mod charts;
pub mod from_app;
pub mod from_profile;
pub mod page;
