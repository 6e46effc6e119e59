pub mod ascript;
