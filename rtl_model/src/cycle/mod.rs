//! The cycle-accurate model: clocked stages as pure step functions with two-phase register
//! commit, bounded valid/ready FIFOs, the hardware configuration, the node-memory model and
//! waveform recording. The stages and walker pool that use them build on these pieces.
pub mod bram;
pub mod clocked;
pub mod completion_wheel;
pub mod fifo;
pub mod hw_config;
pub mod memory;
pub mod stage_stats;
pub mod unit_pipe;
pub mod walk_op;
pub mod walker_pool;
pub mod waves;
