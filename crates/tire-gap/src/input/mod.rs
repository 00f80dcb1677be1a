//! Reading measured data: CSV with unit-suffixed column names, and TYDEX .tdx files.
