// Placeholder so a stage with only main.cpp still has a (empty) library.
