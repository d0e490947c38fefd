VALUE = "libpkg"
