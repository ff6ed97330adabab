//! C ABI for Fractum. The API itself lands with the embedding issue; this crate is a
//! workspace member from the start so that the layout matches docs/architecture.md.
