//! The HMMWV 4WD driveline (being built).
