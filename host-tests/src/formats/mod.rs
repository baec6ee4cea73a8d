//! File formats: recordings in (CSV of ADC codes for `replay`, named columns for `allan` and
//! `drift`), SVG charts out, and numbers in messages.

pub mod chart;
pub mod columns;
pub mod lines;
pub mod number;
pub mod plot;
pub mod recording;
