"""The tests, one folder per part of the package (runs/, study/, teachers/, ...). Each folder is a
package so that two test files of the same name in different folders do not clash."""
