// svo_top_checks: what svo_top builds, by structure. A hardware package (svo_hw_pkg, from
// `sim hardware --sv-package`) or a parameter it cannot follow does not elaborate: each
// refusal instantiates a module that does not exist, whose name says what is built (e.g.
// svo_top_builds_walker_pool_contexts_per_walker_1_to_16), so the tool's error names the
// reason. The model refuses the same configurations in its own validation where it has them
// (rtl_model/src/cycle/hw_config/validate.rs); tests/cocotb_benches.rs checks a refusal by name.
//
// Pipeline position: none; elaboration only (no ports, no logic), instantiated by svo_top
// with its parameters.
`timescale 1ns/1ps
`default_nettype none
module svo_top_checks
    import svo_hw_pkg::*;
#(
    parameter int STORE_WORDS = 262144,
    parameter int LOAD_BURST = 32,
    parameter int NODE_PORTS = 1,
    parameter int NODE_DW = 64,
    parameter int STEP_LATENCY = 4,
    parameter int STACK_DEPTH = 21,
    parameter int NINST = 128,
    parameter int KEYN = 16,
    parameter int DIR_BURST = 16,
    parameter int DIR_DEPTH = 64
) ();
    localparam int LANES = SPHERE_UNITS;
    localparam int WK = TRANSFORM_UNITS;
    localparam int CONTEXTS = WALKER_POOL_CONTEXTS_PER_WALKER;
    localparam int WALKERS = WALKER_POOL_WALKERS;
    localparam bit HAS_STORE = NODE_MEMORY_ONCHIP_LEVELS != 0;
    localparam bit HAS_CACHE = NODE_MEMORY_ONCHIP_LEVELS != 21;
    generate
        // Walk-issue lanes (docs/cycle-model.md §2.1, "Walk issue of width k"): k transforms,
        // k lanes of three reciprocals and k walker roots with the k-wide glue (FIFOs,
        // dispatch, retire, record): svo_walk_wide and svo_walker_pool's K at k = 1 and 2.
        // Unequal units (the model's k is the widest) and k above 2 (record_to_write has two
        // push ports in svo_hit_buffer) are not built.
        if ((WK != 1 && WK != 2) || RECIPROCAL_UNITS != 3 * WK || WALKER_ROOT_UNITS != WK)
        begin : unsupported_walk_lanes
            svo_top_builds_walk_issue_lanes_1_or_2_transform_k_reciprocal_3k_walker_root_k bad();
        end
        // The front end: the hit buffer, at most SORTER_LANES sphere lanes (svo_front's
        // keys), the sorter's latency its network depth (svo_sorter).
        if (HIT_BUFFER_PRESENT == 0 || LANES > SORTER_LANES
            || UNITS_SORTER_LATENCY_CYCLES != SORTER_NET_DEPTH) begin : unsupported_front
            svo_top_builds_the_hit_buffer_and_the_models_sorter bad();
        end
        // The walker pool (svo_walker_pool): 1..64 walkers of 1..16 contexts, one request port
        // and one slot a cycle each, the package's step latency and stack. No bound on the
        // contexts in all: the pool's scheduler is per walker (R x R) plus pool-wide keys.
        if (WALKERS < 1 || WALKERS > 64) begin : unsupported_walkers
            svo_top_builds_walker_pool_walkers_1_to_64 bad();
        end
        if (CONTEXTS < 1 || CONTEXTS > 16) begin : unsupported_contexts
            svo_top_builds_walker_pool_contexts_per_walker_1_to_16 bad();
        end
        // Node words come from the on-chip store (svo_onchip_store: the model's banks, ports,
        // latency and combining), from the node cache (svo_node_cache_axi), or from both:
        // - levels 21: the store holds every level of every image: the model must keep them
        //   all on chip too, and the store's words must fit its byte budget (a scene the store
        //   holds is then all on chip in the model as well);
        // - levels 0: the cache, attribute records included;
        // - levels 1..8: each image's top levels are a prefix of its words (docs/svo-format.md
        //   §4, images lay their top 8 levels out first), the first ONCHIP_WORDS[i] words of
        //   image i, read from the store; every other read through the cache. Levels 9..20
        //   add scattered groups after the prefix in the model (memory/layout.rs): not built.
        if (NODE_MEMORY_ONCHIP_LEVELS > 8 && NODE_MEMORY_ONCHIP_LEVELS != 21)
        begin : unsupported_onchip_levels
            svo_top_needs_node_memory_onchip_levels_0_to_8_or_21 bad();
        end
        if (HAS_STORE && 64'(STORE_WORDS) * 4 > 64'(NODE_MEMORY_ONCHIP_MAX_BYTES))
        begin : unsupported_onchip_bytes
            svo_top_STORE_WORDS_over_node_memory_onchip_max_bytes bad();
        end
        if (HAS_STORE && NODE_MEMORY_ONCHIP_LATENCY < 2) begin : unsupported_onchip_latency
            svo_top_needs_node_memory_onchip_latency_2_or_more bad();
        end
        // The cache: attribute records through it too (their own AXI masters would need the
        // model's uncached timing beside the cache's; not built), and the AXI path's fixed
        // three cycles (AR registered, R registered, the fill written) inside dram.latency
        // (svo_node_cache_axi.v: an external memory of D cycles is dram.latency D + 3).
        if (HAS_CACHE && !NODE_MEMORY_CACHE_ATTR_CACHED) begin : unsupported_cached_attr
            svo_top_with_node_memory_onchip_levels_0_to_8_needs_cache_attr_cached_true bad();
        end
        if (HAS_CACHE && NODE_MEMORY_DRAM_LATENCY < 3) begin : unsupported_cached_latency
            svo_top_with_node_memory_onchip_levels_0_to_8_needs_dram_latency_3_or_more bad();
        end
        if (HAS_CACHE && (NODE_MEMORY_CACHE_LINE_BYTES > 128 || NODE_MEMORY_CACHE_LINE_BYTES < 8))
        begin : unsupported_cached_line
            svo_top_with_node_memory_onchip_levels_0_to_8_needs_cache_line_bytes_8_to_128 bad();
        end
        if (HAS_CACHE && (NODE_PORTS != (NODE_MEMORY_DRAM_BYTES_PER_CYCLE
            + NODE_MEMORY_CACHE_LINE_BYTES - 1) / NODE_MEMORY_CACHE_LINE_BYTES
            || NODE_DW != NODE_MEMORY_CACHE_LINE_BYTES * 8))
        begin : bad_node_ports
            svo_top_NODE_PORTS_NODE_DW_are_derived_do_not_set bad();
        end
        if (HAS_STORE && (STORE_WORDS < NODE_MEMORY_ONCHIP_BANKS
            || STORE_WORDS % NODE_MEMORY_ONCHIP_BANKS != 0))
        begin : bad_store_words
            svo_top_STORE_WORDS_a_multiple_of_node_memory_onchip_banks bad();
        end
        if (LOAD_BURST < 1 || LOAD_BURST > 256) begin : bad_load_burst
            svo_top_LOAD_BURST_1_to_256 bad();
        end
        // Attribute records go to the per-walker masters: up to WALKERS a cycle, each served
        // in its cycle (no lookup port or DRAM cycle waits).
        if (!HAS_CACHE && WALKERS > 1 && NODE_MEMORY_CACHE_PORTS < WALKERS) begin : unsupported_cache_ports
            svo_top_with_several_walkers_needs_node_memory_cache_ports_of_walkers bad();
        end
        if (!HAS_CACHE && NODE_MEMORY_CACHE_LINE_BYTES * WALKERS > NODE_MEMORY_DRAM_BYTES_PER_CYCLE)
        begin : unsupported_dram_bus
            svo_top_needs_node_memory_dram_bytes_per_cycle_of_walkers_lines bad();
        end
        if (WALKER_POOL_READ_PORTS != 1 && !(WALKER_POOL_READ_PORTS == 0 && CONTEXTS == 1))
        begin : unsupported_read_ports
            svo_top_builds_walker_pool_read_ports_1 bad();
        end
        // The pool's registered response and request (walker_pool.rs, issue 29): 0 or 1 each
        // (the model's validate refuses more).
        if (WALKER_POOL_RESPONSE_REGISTER_CYCLES > 1) begin : unsupported_response_register
            svo_top_builds_walker_pool_response_register_cycles_0_or_1 bad();
        end
        if (WALKER_POOL_REQUEST_REGISTER_CYCLES > 1) begin : unsupported_request_register
            svo_top_builds_walker_pool_request_register_cycles_0_or_1 bad();
        end
        if (WALKER_POOL_STEP_CYCLES != 1) begin : unsupported_step_cycles
            svo_top_builds_walker_pool_step_cycles_1 bad();
        end
        if (WALKER_POOL_STEP_LATENCY_CYCLES != STEP_LATENCY) begin : unsupported_step_latency
            svo_top_walker_pool_step_latency_cycles_differs_from_STEP_LATENCY bad();
        end
        if (WALKER_POOL_STACK_DEPTH != STACK_DEPTH) begin : unsupported_stack_depth
            svo_top_walker_pool_stack_depth_differs_from_STACK_DEPTH bad();
        end
        // The attribute memory behind m_axi_* answers every read in one fixed latency, in order;
        // with several contexts two attribute reads can overlap, and the pool merges them as
        // the model's MSHRs do only for uncached 8-byte attribute lines (svo_walker_pool.v).
        // The fixed latency is the bench's: the uncached DRAM read's (dram.latency + 1).
        if (!HAS_CACHE && WALKERS * CONTEXTS > 1 && NODE_MEMORY_CACHE_ATTR_CACHED) begin : unsupported_attr_cached
            svo_top_with_several_contexts_needs_node_memory_cache_attr_cached_false bad();
        end
        if (!HAS_CACHE && WALKERS * CONTEXTS > 1 && NODE_MEMORY_CACHE_LINE_BYTES != 8) begin : unsupported_line_bytes
            svo_top_with_several_contexts_needs_node_memory_cache_line_bytes_8 bad();
        end
        if (!HAS_CACHE && WALKERS * CONTEXTS > 1 && !NODE_MEMORY_DRAM_BACKEND_IS_BUILTIN) begin : unsupported_backend
            svo_top_with_several_contexts_needs_node_memory_dram_backend_BuiltIn bad();
        end
        if (!HAS_CACHE && NODE_MEMORY_CACHE_ATTR_CACHED
            && NODE_MEMORY_CACHE_HIT_LATENCY != NODE_MEMORY_ONCHIP_LATENCY)
        begin : unsupported_hit_latency
            svo_top_needs_node_memory_cache_hit_latency_equal_to_onchip_latency bad();
        end
        if (!HAS_CACHE && NODE_MEMORY_DRAM_LATENCY + 1 != NODE_MEMORY_ONCHIP_LATENCY)
        begin : unsupported_dram_latency
            svo_top_needs_node_memory_dram_latency_plus_1_equal_to_onchip_latency bad();
        end
        if (NINST < LANES || NINST > 128 || KEYN < LANES || KEYN > 63
            || KEYN % SORTER_LANES != 0) begin : bad_instances
            svo_top_NINST_LANES_to_128_KEYN_a_multiple_of_the_sorter_lanes_to_63 bad();
        end
        if (DIR_BURST < 1 || DIR_BURST > 256 || DIR_DEPTH < DIR_BURST) begin : bad_dir_fifo
            svo_top_DIR_DEPTH_must_hold_a_burst bad();
        end
    endgenerate
endmodule
`default_nettype wire
