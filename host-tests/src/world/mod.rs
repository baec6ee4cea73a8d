//! The simulated world the device lives in: sensor noise and ADC quantisation
//! ([`noise`]), scenes composed from small effects ([`scene`]), and a hand on a desk
//! ([`desk`]). Everything here ends as ADC codes; nothing here runs the core.

pub mod desk;
pub mod hand;
pub mod noise;
pub mod scene;
