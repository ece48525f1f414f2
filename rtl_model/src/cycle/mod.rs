//! The cycle-accurate model's parts: the clock with one commit point per edge and cycle stamps,
//! bounded valid/ready FIFOs, fixed-latency unit pipes, block RAM, the walker pool, the
//! node-memory model, the hardware configuration and waveform recording. The frame pipeline
//! (`svo_sim::models::cycle`) evaluates its stages over these pieces and commits them at the
//! edge.
pub mod bram;
pub mod clocked;
pub mod completion_wheel;
pub mod fifo;
pub mod hw_config;
pub mod hw_package;
pub mod memory;
pub mod part;
pub mod ray_order;
pub mod stage_stats;
#[cfg(test)]
mod test_rng;
pub mod unit_lanes;
pub mod unit_latency;
pub mod unit_pipe;
pub mod walk_op;
pub mod walk_timing;
pub mod walker_pool;
pub mod waves;
