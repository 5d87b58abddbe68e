//! RGB → smooth spectrum upsampling (TODO(spectrum helper): Jakob & Hanika 2019 sigmoid
//! polynomial, fitted per colour when a scene is built).
