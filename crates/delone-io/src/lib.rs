//! delone-io placeholder.
