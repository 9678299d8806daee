//! Tests of the viscous damping and current in the model.
