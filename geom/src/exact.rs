//! Exact point evaluator (in progress).
