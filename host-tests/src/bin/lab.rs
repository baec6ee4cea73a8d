//! The imu-mouse lab CLI (being built).
fn main() {}
