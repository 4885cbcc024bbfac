//! Sun direction models.
