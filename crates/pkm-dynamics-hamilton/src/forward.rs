//! Forward dynamics (placeholder, filled below).
