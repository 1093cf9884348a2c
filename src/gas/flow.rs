//! Pressure losses of the reservoir connection: a compressible orifice (isentropic nozzle,
//! Saint-Venant) in series with laminar pipe friction (Hagen–Poiseuille).
