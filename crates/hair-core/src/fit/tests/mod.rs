//! Tests of the fit: synthetic grooms with known answers, and the TressFX samples.
