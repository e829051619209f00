//! Writing results: files written whole or not at all (PNG, GIF, video,
//! JSON, text), the wind-slice pictures, the debug views' keys, and the tables printed or saved. It
//! computes nothing: the commands hand it what they measured.

pub mod bench;
pub mod claim;
pub mod files;
pub mod legend;
pub mod npy;
pub mod plan_view;
pub mod render;
pub mod reproduce;
pub mod space_time;
pub mod spectrum;
pub mod timing;
pub mod trace;
pub mod video;
pub mod warnings;
pub mod wind;
pub mod wind_slices;
